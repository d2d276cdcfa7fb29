#include "farm/farm_job.h"

#include <algorithm>
#include <filesystem>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "util/error.h"

namespace pluvia::farm {

int chunkCount(const FarmJob& job) {
  const int64_t frames = job.lastFrame - job.firstFrame + 1;
  return static_cast<int>((frames + job.chunkFrames - 1) / job.chunkFrames);
}

std::pair<int64_t, int64_t> chunkFrames(const FarmJob& job, int index) {
  const int64_t first = job.firstFrame + int64_t(index) * job.chunkFrames;
  return {first, std::min(first + job.chunkFrames - 1, job.lastFrame)};
}

bool isMovieJob(const FarmJob& job) {
  return job.output.isMovie();
}

std::string chunkOutput(const FarmJob& job) {
  if (!isMovieJob(job)) return job.output.path;
  const std::string name = std::filesystem::path(job.output.path).stem().string();
  return (std::filesystem::path(job.farmDir) / "frames" / (name + ".####.tif")).string();
}

std::string shellQuote(const std::string& word) {
  if (!word.empty() && word.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                              "0123456789_-.,/:=+@%") == std::string::npos)
    return word;
  std::string quoted = "'";
  for (char c : word) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

namespace {

std::string presetArguments(const FarmJob& job) {
  std::string args = "-p " + shellQuote(job.preset);
  for (const std::string& set : job.sets) args += " --set " + shellQuote(set);
  return args;
}

std::string quotedArguments(const std::vector<std::string>& arguments) {
  std::string line;
  for (const std::string& argument : arguments) line += " " + shellQuote(argument);
  return line;
}

// A fixed count, or the allocation in every Slurm mode: --cpus-per-task sets
// SLURM_CPUS_PER_TASK; a whole-node allocation (--exclusive) sets only SLURM_CPUS_ON_NODE; and
// inside any job nproc counts the CPUs its cgroup allows.
std::string threadsArgument(const FarmJob& job) {
  return job.threads > 0 ? std::to_string(job.threads)
                         : "\"${SLURM_CPUS_PER_TASK:-${SLURM_CPUS_ON_NODE:-$(nproc)}}\"";
}

}  // namespace

std::string prepareCommand(const FarmJob& job) {
  return fmt::format("{} prepare {} {} --cache {}{}", shellQuote(job.pluvia), shellQuote(job.input),
                     presetArguments(job), shellQuote(job.cacheDir),
                     quotedArguments(job.prepareOptions));
}

std::string renderCommand(const FarmJob& job, const std::string& frames) {
  // The frame range stays open to the shell (it may be "$FIRST-$LAST"): double quotes.
  return fmt::format(
      "{} render {} {} -o {} --frames \"{}\" --cache {} --require-cache --skip-existing "
      "--threads {}{}{}",
      shellQuote(job.pluvia), shellQuote(job.input), presetArguments(job),
      shellQuote(chunkOutput(job)), frames, shellQuote(job.cacheDir), threadsArgument(job),
      isMovieJob(job) ? " --tiff-type float" : "", quotedArguments(job.renderOptions));
}

std::string assembleCommand(const FarmJob& job) {
  return fmt::format("{} farm assemble {} -o {} --fps {} --frames {}-{} {}{}",
                     shellQuote(job.pluvia), shellQuote(chunkOutput(job)),
                     shellQuote(job.output.path), job.fps, job.firstFrame, job.lastFrame,
                     presetArguments(job), quotedArguments(job.assembleOptions));
}

std::string farmJobJson(const FarmJob& job) {
  nlohmann::json json{{"pluvia", job.pluvia},
                      {"input", job.input},
                      {"preset", job.preset},
                      {"sets", job.sets},
                      {"output", job.output.path},
                      {"cache", job.cacheDir},
                      {"farm_dir", job.farmDir},
                      {"working_dir", job.workingDir},
                      {"first_frame", job.firstFrame},
                      {"last_frame", job.lastFrame},
                      {"chunk_frames", job.chunkFrames},
                      {"fps", job.fps},
                      {"threads", job.threads},
                      {"render_options", job.renderOptions},
                      {"prepare_options", job.prepareOptions},
                      {"assemble_options", job.assembleOptions},
                      {"ocio", job.ocioConfig}};
  return json.dump(2) + "\n";
}

namespace {

// More chunks than any scheduler's job array holds (Slurm's MaxArraySize tops out at 4 million):
// a farm.json asking for them was edited by hand or damaged.
constexpr int64_t kMaxChunks = 4000000;

// Frame numbers beyond this are no clip's; within it, frame arithmetic never overflows.
constexpr int64_t kMaxFrameNumber = 1'000'000'000'000;

// An integer field, refused when it is no integer or outside [min, max]: JSON's 1e300 or
// -2^63 read into an int64_t would wrap.
int64_t integerField(const nlohmann::json& json, const std::string& key, int64_t min, int64_t max,
                     const std::string& path) {
  const nlohmann::json& value = json.at(key);
  if (!value.is_number_integer() ||
      (value.is_number_unsigned() && value.get<uint64_t>() > uint64_t(max)) ||
      value.get<int64_t>() < min || value.get<int64_t>() > max)
    throw Error(fmt::format("{}: {} is {}; it must be an integer from {} to {}", path, key,
                            value.dump(), min, max),
                {"farm", {}, path});
  return value.get<int64_t>();
}

// The frame range and chunk size a farm.json states, before anything divides by or loops over
// them.
void checkFrames(const FarmJob& job, const std::string& path) {
  const auto bad = [&](const std::string& key, const std::string& why) {
    return Error(fmt::format("{}: {} {}", path, key, why), {"farm", {}, path});
  };
  if (job.chunkFrames < 1)
    throw bad("chunk_frames",
              fmt::format("is {}; a chunk holds at least 1 frame", job.chunkFrames));
  if (job.lastFrame < job.firstFrame)
    throw bad("last_frame",
              fmt::format("{} is before first_frame {}", job.lastFrame, job.firstFrame));
  const int64_t chunks = (job.lastFrame - job.firstFrame) / job.chunkFrames + 1;
  if (chunks > kMaxChunks)
    throw bad("last_frame",
              fmt::format("{} makes {} chunks of {} frames from {}; at most {}", job.lastFrame,
                          chunks, job.chunkFrames, job.firstFrame, kMaxChunks));
}

}  // namespace

FarmJob farmJobFromJson(const std::string& text, const std::string& path) {
  try {
    const nlohmann::json json = nlohmann::json::parse(text);
    FarmJob job;
    job.pluvia = json.at("pluvia");
    job.input = json.at("input");
    job.preset = json.at("preset");
    job.sets = json.at("sets").get<std::vector<std::string>>();
    job.output = OutputTarget::classify(json.at("output").get<std::string>());
    job.cacheDir = json.at("cache");
    job.farmDir = json.at("farm_dir");
    job.workingDir = json.at("working_dir");
    job.firstFrame = integerField(json, "first_frame", -kMaxFrameNumber, kMaxFrameNumber, path);
    job.lastFrame = integerField(json, "last_frame", -kMaxFrameNumber, kMaxFrameNumber, path);
    job.chunkFrames = int(integerField(json, "chunk_frames", 1, 1'000'000, path));
    job.fps = json.at("fps");
    if (!(job.fps > 0.0 && job.fps <= 1000.0))
      throw Error(fmt::format("{}: fps is {}; it must be in (0, 1000]", path, job.fps),
                  {"farm", {}, path});
    job.threads = int(integerField(json, "threads", 0, 1024, path));
    // Farm folders written before these were recorded hold none.
    job.renderOptions = json.value("render_options", std::vector<std::string>{});
    job.prepareOptions = json.value("prepare_options", std::vector<std::string>{});
    job.assembleOptions = json.value("assemble_options", std::vector<std::string>{});
    job.ocioConfig = json.value("ocio", std::string());
    checkFrames(job, path);
    return job;
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw Error(fmt::format("{} is not a pluvia farm job description: {}", path, e.what()),
                {"farm", {}, path});
  }
}

}  // namespace pluvia::farm
