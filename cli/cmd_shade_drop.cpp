// `pluvia shade-drop`: the linear RGB radiance one raindrop sends toward the camera along a
// view direction, lit by an equirect environment, by any of the drop-shading methods.
#include <cmath>
#include <cstdio>
#include <iostream>

#include <fmt/format.h>

#include "commands.h"
#include "optics/drop_shading.h"
#include "optics/drop_trace.h"
#include "optics/environment_file.h"
#include "util/error.h"

namespace pluvia::cli {
namespace {

std::array<double, 3> parseTriple(const std::string& text, const std::string& option) {
  std::array<double, 3> v{};
  char extra = 0;
  if (std::sscanf(text.c_str(), "%lf,%lf,%lf%c", &v[0], &v[1], &v[2], &extra) != 3) {
    throw UsageError(
        fmt::format("{} expects three comma-separated numbers, got '{}'", option, text));
  }
  for (double x : v) {
    if (!std::isfinite(x))
      throw UsageError(fmt::format("{} holds a non-finite number: '{}'", option, text));
  }
  return v;
}

std::array<double, 3> unitDirection(const std::string& text) {
  std::array<double, 3> d = parseTriple(text, "--dir");
  const double length = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  if (!(length > 1e-12))
    throw UsageError(fmt::format("--dir must not be the zero vector, got '{}'", text));
  for (double& x : d) x /= length;
  return d;
}

}  // namespace

void addShadeDropCommand(CLI::App& app, Invocation& invocation) {
  auto* cmd =
      app.add_subcommand("shade-drop", "radiance of one raindrop toward the camera (linear RGB)");
  struct Args {
    std::string env, dir, method = "default", eta;
    int order = optics::kPaperShOrder;
    int samples = optics::TraceSettings{}.samples;
    bool dispersion = false;
  };
  auto args = std::make_shared<Args>();
  cmd->add_option("--env", args->env, "equirect HDR environment (.exr, .hdr)")->required();
  cmd->add_option("--dir", args->dir, "view direction X,Y,Z: camera to drop, world +Y up")
      ->required();
  auto* method = cmd->add_option("--method", args->method, "default | paper | trace")
                     ->check(CLI::IsMember({"default", "paper", "trace"}));
  auto* order = cmd->add_option("--order", args->order, "SH order of --method paper (paper: 3)")
                    ->check(CLI::Range(0, 8));
  auto* samples = cmd->add_option("--samples", args->samples, "rays of --method trace")
                      ->check(CLI::Range(1, 1 << 26));
  auto* eta = cmd->add_option("--eta", args->eta, "refractive index R,G,B (default 1.333 for all)");
  cmd->add_flag("--dispersion", args->dispersion, "water's dispersion: eta 1.331,1.333,1.338")
      ->excludes(eta);
  (void)method;
  cmd->callback([=, &invocation] {
    const optics::DropMethod chosen = optics::parseDropMethod(args->method);
    if (order->count() && chosen != optics::DropMethod::Paper)
      throw UsageError("--order applies to --method paper only");
    if (samples->count() && chosen != optics::DropMethod::Trace)
      throw UsageError("--samples applies to --method trace only");
    const std::array<double, 3> view = unitDirection(args->dir);
    std::array<double, 3> etaRgb = {optics::kWaterEta, optics::kWaterEta, optics::kWaterEta};
    if (args->dispersion) etaRgb = optics::kWaterEtaDispersion;
    if (!args->eta.empty()) etaRgb = parseTriple(args->eta, "--eta");
    for (double e : etaRgb) {
      if (!(e > 1.0 && e <= 3.0))
        throw UsageError(fmt::format("--eta values must be in (1, 3], got {}", e));
    }
    const EquirectMap env = optics::loadEnvironment(args->env);

    std::array<double, 3> radiance{};
    switch (chosen) {
      case optics::DropMethod::Default: {
        const EquirectMap map =
            optics::buildDropRadianceMap(env, optics::channelOptics(etaRgb, optics::kDefaultTerms));
        const auto c = sampleEquirect(map, float(view[0]), float(view[1]), float(view[2]));
        radiance = {c[0], c[1], c[2]};
        break;
      }
      case optics::DropMethod::Paper: {
        const optics::PaperShading paper = optics::preparePaperShading(env, etaRgb, args->order);
        radiance = optics::shadePaper(paper, env, view);
        break;
      }
      case optics::DropMethod::Trace: {
        optics::TraceSettings trace;
        trace.samples = args->samples;
        radiance = optics::traceDropRadiance(env, view, etaRgb, trace);
        break;
      }
    }
    std::cout << fmt::format("{:.7g} {:.7g} {:.7g}\n", radiance[0], radiance[1], radiance[2]);
    invocation.exitCode = 0;
  });
}

}  // namespace pluvia::cli
