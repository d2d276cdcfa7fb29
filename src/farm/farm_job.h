#pragma once
// A render split for a farm: one prepare job (pluvia prepare: the per-clip analysis into the
// shared cache), render chunks of N frames (one job array, each task `pluvia render --frames
// A-B --skip-existing --require-cache`, so a requeued task resumes) after it, and for a movie an
// assembly job that encodes the chunks' frames into the movie after them. Scheduler-neutral:
// the Slurm scripts (farm/slurm.h) and the Deadline/OpenCue templates (docs/FARM.md) run the
// same commands.
#include <cstdint>
#include <string>
#include <vector>

#include "io/output_target.h"

namespace pluvia::farm {

struct FarmJob {
  std::string pluvia;  // absolute path of the pluvia binary the nodes run
  std::string input;   // absolute
  std::string preset;  // a shipped name, or an absolute path
  std::vector<std::string> sets;
  OutputTarget output;     // absolute: a sequence pattern or a movie
  std::string cacheDir;    // absolute, shared by every node
  std::string farmDir;     // absolute: scripts, logs, task records and a movie's frames
  std::string workingDir;  // where the jobs run, for relative paths in `sets` (depth.file=...)
  int64_t firstFrame = 0;  // the clip's frames to render (contiguous)
  int64_t lastFrame = 0;
  int chunkFrames = 10;
  double fps = 24;  // a movie's, as the one-machine render writes it
  // Threads per chunk; 0: the node's Slurm allocation ($SLURM_CPUS_PER_TASK, else 2).
  int threads = 0;
  // What the render was asked to write (cli/common.h's RenderOutputOptions, as `pluvia render`
  // arguments): the chunks get them all but a movie's --codec, which goes to the assembly, and
  // the prepare job gets --proxy (the analysis is cached per proxy size).
  std::vector<std::string> renderOptions;
  std::vector<std::string> prepareOptions;
  std::vector<std::string> assembleOptions;
  // Exported in every job, so that a node renders in the colour config the submitting shell had.
  std::string ocioConfig;
};

// How many chunks, and chunk `index`'s frames.
int chunkCount(const FarmJob& job);
std::pair<int64_t, int64_t> chunkFrames(const FarmJob& job, int index);
bool isMovieJob(const FarmJob& job);
// What the chunks render into: the output itself, or for a movie a float TIFF sequence in the
// farm folder (frames/NAME.####.tif), which the assembly job encodes exactly as a one-machine
// render would have: the frames keep the very samples the movie writer takes, super-whites and
// sub-blacks too (a 16-bit TIFF would clip them to [0, 1]).
std::string chunkOutput(const FarmJob& job);

// The shell commands (quoted, one line each) a node runs. `frames` is "A-B" or a shell
// expression giving it ("$FIRST-$LAST").
std::string prepareCommand(const FarmJob& job);
std::string renderCommand(const FarmJob& job, const std::string& frames);
std::string assembleCommand(const FarmJob& job);

// A word quoted for sh, unless it needs none.
std::string shellQuote(const std::string& word);

// The farm folder's description of the job (farm.json), read by `pluvia farm status`.
std::string farmJobJson(const FarmJob& job);
FarmJob farmJobFromJson(const std::string& text, const std::string& path);

}  // namespace pluvia::farm
