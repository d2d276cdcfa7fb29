#include <iostream>
#include <memory>
#include <optional>

#include <fmt/format.h>

#include "commands.h"
#include "common.h"
#include "pipeline/camera_settings.h"
#include "pipeline/plate_lens.h"
#include "pipeline/render_job.h"
#include "stages/lights_settings.h"
#include "stages/plate_shutter.h"
#include "stages/registry.h"
#include "util/log.h"

namespace pluvia::cli {

namespace {

// A render session on the plan's clip, for what a render finds once per clip (the lamps, the
// shutter), its log held to warnings while it lives: the plan prints what it found itself.
class QuietSession {
 public:
  QuietSession(const std::string& input, std::optional<int64_t> movieFirstFrame,
               const Preset& preset, const std::string& cache)
      : level_(log::level()) {
    request_.input = input;
    request_.movieFirstFrame = movieFirstFrame;
    request_.cacheDir = cache;
    request_.progress = false;
    log::setLevel(log::Level::Warning);
    session_ = std::make_unique<RenderSession>(request_, preset, allStages(), times_);
  }
  ~QuietSession() {
    session_.reset();  // what it logs as it ends, held too
    log::setLevel(level_);
  }
  RenderSession& operator*() { return *session_; }
  RenderSession* operator->() { return session_.get(); }

 private:
  log::Level level_;
  RenderRequest request_;
  StageTimes times_;
  std::unique_ptr<RenderSession> session_;
};

// lights.find: the lamps the plate gives, one line each, on stderr (stdout holds only the resolved
// preset's JSON, for a script to load) (they are
// found in the clip's still and placed at the depth the depth stage gives its first frame, as a
// render does once per clip). Only the depth and lights stages are prepared.
void printFoundLamps(const std::string& input, std::optional<int64_t> movieFirstFrame,
                     const Preset& preset, const std::string& cache) {
  const LightsSettings lights = lightsSettings(preset);
  if (!lights.find) return;
  std::optional<std::vector<FoundLamp>> found;
  {
    QuietSession session(input, movieFirstFrame, preset, cache);
    if (!session->plan().runs("lights")) return;
    session->prepareStagesNamed({"depth", "lights"});
    found = session->clipContext().foundLamps;
  }
  std::cerr << fmt::format("lamps found in the plate (lights.find): {}\n",
                           found ? found->size() : 0);
  if (!found) return;
  for (size_t i = 0; i < found->size(); ++i) {
    const FoundLamp& l = (*found)[i];
    std::cerr << fmt::format(
        "  lamp {}: pixel ({:.1f}, {:.1f}), {} px, depth {:.2f} m, colour ({:.3f}, {:.3f}, "
        "{:.3f}), intensity {:.4g}, world ({:.3f}, {:.3f}, {:.3f}) m, radius {:.3f} m\n",
        i, l.xPx, l.yPx, l.areaPx, l.depthMeters, l.rgb[0], l.rgb[1], l.rgb[2], l.intensity,
        l.worldMeters[0], l.worldMeters[1], l.worldMeters[2], l.radiusMeters);
  }
}

// The shutter the rain and splashes are filmed with and where it comes from (the preset, or the
// plate: its metadata, its motion blur measured on 7 frames, else the 180-degree shutter), and
// the lens the rain is filmed through (the plate's where its files state it), as a render finds
// them.
std::string cameraLines(const std::string& input, std::optional<int64_t> movieFirstFrame,
                        const Preset& preset, const std::string& cache) {
  QuietSession session(input, movieFirstFrame, preset, cache);
  if (!session->plan().runs("rain") && !session->plan().runs("splash")) return "";
  CameraSettings camera = cameraSettings(preset);
  const PlateLens& lens = session->clipContext().plateLens;
  const std::string lensText = session->plan().runs("rain")
                                   ? "  lens " + lensLine(withPlateLens(camera, lens), lens) + "\n"
                                   : std::string();
  const double fps = session->clipContext().fps;
  std::string source = presetShutterSource(camera, fps);
  if (source.empty()) {
    // Measured afresh: the plan leaves the cache as it found it.
    session->clipContext().cache = nullptr;
    const PlateShutter& shutter = clipPlateShutter(session->clipContext());
    camera.plateShutterSeconds = shutter.seconds;
    source = shutter.source + "; camera.exposure_s or camera.shutter_angle_deg sets another";
  }
  return fmt::format("  shutter 1/{:.0f} s: {}\n", 1.0 / camera.exposureSecondsAt(fps, 0.0),
                     source) +
         lensText;
}

}  // namespace

void addPlanCommand(CLI::App& app, Invocation& invocation) {
  auto* cmd =
      app.add_subcommand("plan", "say what a render would run and what it leaves out, and why");
  struct Args {
    std::string input, preset, cache;
    std::vector<std::string> sets;
    bool resolved = false;
    std::optional<int64_t> startFrame;
  };
  auto args = std::make_shared<Args>();
  addClipPresetOptions(cmd, args->input, args->preset, args->sets);
  cmd->add_option("--cache", args->cache, "cache folder for per-clip analysis");
  addStartFrameOption(cmd, args->startFrame);
  cmd->add_flag("--resolved", args->resolved,
                "print the fully resolved preset as JSON instead (stdout), and the lamps found "
                "in the plate (lights.find), one line each, on stderr");
  cmd->callback([=] {
    Preset preset = loadPreset(args->preset, args->sets);
    if (args->resolved) {
      printFoundLamps(args->input, args->startFrame, preset, args->cache);
      std::cout << preset.json().dump(2) << "\n";
      return;
    }
    ClipInfo clip;
    Plan plan = planJob(args->input, args->startFrame, preset, args->cache, allStages(), &clip);
    std::cout << fmt::format(
        "plan for {} ({}x{}, {} frames {}-{}, {} fps) with preset {} (hash {}):\n", clip.path,
        clip.width, clip.height, clip.frames.size(), clip.frames.front(), clip.frames.back(),
        clip.fps, preset.source(), preset.hash());
    std::cout << plan.text();
    std::cout << cameraLines(args->input, args->startFrame, preset, args->cache);
  });
}

}  // namespace pluvia::cli
