#pragma once
// Helpers shared by the subcommands.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>

#include "option_values.h"
#include "pipeline/render_job.h"
#include "preset/preset.h"

namespace pluvia::cli {

// "1001-1048" or "12" -> (first, last). Throws UsageError naming the text.
std::pair<int64_t, int64_t> parseFrameRange(const std::string& text);
// --frames of render and preview: a range sets the request's first and last frame, a stepped or
// comma list ("1001-1100x2", "1,5,9") its frame list (io/frame_list.h). Throws UsageError.
void setFrames(RenderRequest& request, const std::string& text);
// --proxy: throws UsageError unless `scale` is in (0, 1].
void checkProxyScale(double scale);
// --start-frame, of every command that reads a clip as a render does (render, plan, prepare,
// preview, farm slurm): the number of a movie's first frame.
void addStartFrameOption(CLI::App* cmd, std::optional<int64_t>& movieFirstFrame);

// What a render writes besides its frames' pixels: shared by `render` and `farm slurm` (which
// passes them on to its chunks and its assembly) so that the two commands cannot drift.
struct RenderOutputOptions {
  std::string codec = "h264", exrType = "half", exrCompression = "piz", tiffType = "uint16", aov;
  double proxy = 1.0;
  bool makeFolders = false;  // --mkdir
  // The --aov list, checked: each known output once, in the order given.
  std::vector<std::string> aovs() const;
  // These options as `pluvia render` arguments (those the user gave a value other than the
  // default), for a farm chunk's command line.
  std::vector<std::string> renderArguments() const;
  // Throws pluvia::UsageError naming an option given that does nothing for `output`: --codec
  // for an image sequence, --exr-type or --exr-compression for anything but EXR, --tiff-type for
  // anything but TIFF.
  void refuseOptionsNotFor(const std::string& output) const;
  // Set by addRenderOutputOptions: whether each was given.
  const CLI::Option *codecOption = nullptr, *exrTypeOption = nullptr,
                    *exrCompressionOption = nullptr, *tiffTypeOption = nullptr;
};
void addRenderOutputOptions(CLI::App* cmd, RenderOutputOptions& options);
// Resolves a preset against the full schema (every stage's table).
Preset loadPreset(const std::string& nameOrPath, const std::vector<std::string>& overrides);
// The same for a proxy render (--proxy `scale` < 1): the parameters measured in frame pixels
// (blur.sigma_px; the x, y, width and height of lighting.lights regions) are scaled with the
// frame, after the overrides, so they cover at the proxy size what they cover on the full
// frame. Logs each change.
Preset loadPresetForProxy(const std::string& nameOrPath, const std::vector<std::string>& overrides,
                          double scale);
// Throws UsageError when any of `outputs` is one of `inputFiles` ("OPTION OUT is the input file
// IN: refusing to overwrite it"), before anything is written.
// Registers the files the parsed command names as its inputs (INPUT, CLIP, --env, --hdr, a
// preset path) with fs::protectInputs, so that no output, report or log of the run can be written
// over one. A sequence pattern's frames are registered by the command once it has listed them.
void protectNamedInputs(const CLI::App& app);

void refuseOverwritingInput(const std::vector<std::string>& inputFiles, const std::string& option,
                            const std::vector<std::string>& outputs);
// A CLI11 check for options whose empty value would read as not given (`--frames "$RANGE"` with
// RANGE unset rendered the whole clip): an empty value is refused, naming the option.
const CLI::Validator& nonEmptyText();
// A CLI11 check that a number is finite (CLI::Range lets NaN through).
const CLI::Validator& finiteNumber();

// The command line as one shell-quoted string, for logs and metadata.
std::string joinCommandLine(int argc, char** argv);

// The options every command that renders a clip takes alike: INPUT, -p/--preset and --set.
void addClipPresetOptions(CLI::App* cmd, std::string& input, std::string& preset,
                          std::vector<std::string>& sets);
// `relative` beside the running binary's install prefix (the folder above the binary's: the
// repository for build/pluvia, /usr/local for /usr/local/bin/pluvia), else in the current
// directory; "" when it is in neither. Nothing is found through a compiled-in source path.
std::string findBesideInstall(const std::filesystem::path& relative);

}  // namespace pluvia::cli
