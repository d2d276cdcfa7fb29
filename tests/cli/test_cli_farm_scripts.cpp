// The job scripts `farm slurm` writes run nothing but pluvia, whatever the names (adversarial
// S1): `$()` and backticks in paths are data, a newline cannot become a command line (refused
// where an #SBATCH line would have to carry it), a space is quoted for sbatch. A --farm-dir that
// holds someone's files, or whose tasks folder is a link, is refused instead of emptied (S2).
// A task stopped at its time limit is a time-out, not a failure. The scripts are run with bash,
// as a Slurm node would run them; no cluster is needed.
#include <gtest/gtest.h>

#include <filesystem>

#include "test_support.h"
#include "util/fs.h"
#include "util/subprocess.h"

using namespace pluvia;
using namespace pluvia::test;
namespace stdfs = std::filesystem;

namespace {

int runScript(const stdfs::path& script) {
  return runProcess({"env", "SLURM_ARRAY_TASK_ID=0", "SLURM_JOB_ID=7", "bash", script.string()})
      .exitCode;
}

}  // namespace

TEST(CliFarmScripts, NamesInTheScriptsAreDataNotCommands) {
  const stdfs::path dir = freshTempDir("farm_scripts");
  const std::string plate = writeTexturedPlate(dir, 1, 4);
  const stdfs::path marker = dir / "PWNED";

  // $() in the output path, and backticks in --farm-dir: both reach the scripts' commands and
  // the status line; neither runs.
  const stdfs::path out = dir / ("o$(touch " + marker.string() + ")") / "r.####.png";
  const stdfs::path farm = dir / ("f`touch " + marker.string() + "`");
  // The names hold '/': their folders are several levels deep (--mkdir).
  auto r = runPluvia({"farm", "slurm", plate, "-p", "moderate", "-o", out.string(), "--chunk", "2",
                      "--farm-dir", farm.string(), "--mkdir"});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  runScript(farm / "prepare.sbatch");
  runScript(farm / "render.sbatch");
  EXPECT_FALSE(stdfs::exists(marker));
  EXPECT_TRUE(stdfs::exists(farm / "tasks" / "prepare.status"));  // the status line still ran
  EXPECT_TRUE(stdfs::exists(out.parent_path() / "r.0001.png"));   // and so did the render

  // A newline in the output path stays inside its quotes (and the comment that names it).
  const stdfs::path newline = dir / ("x\ntouch " + marker.string() + "\n.####.png");
  r = runPluvia({"farm", "slurm", plate, "-p", "moderate", "-o", newline.string(), "--chunk", "2",
                 "--farm-dir", (dir / "f2").string(), "--mkdir"});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  runScript(dir / "f2" / "prepare.sbatch");
  runScript(dir / "f2" / "render.sbatch");
  EXPECT_FALSE(stdfs::exists(marker));
  EXPECT_TRUE(stdfs::exists(dir / "f2" / "tasks" / "render-0.status"));

  // Where the value would stand on an #SBATCH line, a newline is refused, naming the option.
  r = runPluvia({"farm", "slurm", plate, "-p", "moderate", "-o",
                 (dir / "o3" / "r.####.png").string(), "--chunk", "2", "--partition",
                 "debug\ntouch " + marker.string()});
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find("--partition"), std::string::npos) << r.output;
  r = runPluvia({"farm", "slurm", plate, "-p", "moderate", "-o",
                 (dir / "o4" / "r.####.png").string(), "--chunk", "2",
                 "--sbatch-arg=--time=1:00\ntouch " + marker.string()});
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find("--sbatch-arg"), std::string::npos) << r.output;
  EXPECT_FALSE(stdfs::exists(dir / "o3" / "r.farm" / "render.sbatch"));
}

TEST(CliFarmScripts, ASpaceInThePathIsQuotedOnTheSbatchLines) {
  const stdfs::path dir = freshTempDir("farm_space");
  const std::string plate = writeTexturedPlate(dir, 1, 2);
  const stdfs::path farm = dir / "my shots" / "f";
  const auto r = runPluvia({"farm", "slurm", plate, "-p", "moderate", "-o",
                            (dir / "my shots" / "r.####.png").string(), "--chunk", "2",
                            "--farm-dir", farm.string()});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const std::string script = fs::readTextFile(farm / "render.sbatch");
  EXPECT_NE(script.find("#SBATCH --output=\"" + (farm / "logs").string()), std::string::npos)
      << script;
}

TEST(CliFarmScripts, AFarmFolderHoldingOtherFilesIsRefusedNotEmptied) {
  const stdfs::path dir = freshTempDir("farm_foreign");
  const std::string plate = writeTexturedPlate(dir, 1, 2);
  stdfs::create_directories(dir / "proj" / "tasks");
  writeTextFile(dir / "proj" / "tasks", "todo.txt", "mine");
  writeTextFile(dir / "proj", "jobs.json", "{}");
  auto r = runPluvia({"farm", "slurm", plate, "-p", "moderate", "-o",
                      (dir / "a" / "r.####.png").string(), "--chunk", "2", "--farm-dir",
                      (dir / "proj").string()});
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find("not a pluvia farm folder"), std::string::npos) << r.output;
  EXPECT_TRUE(stdfs::exists(dir / "proj" / "tasks" / "todo.txt"));
  EXPECT_TRUE(stdfs::exists(dir / "proj" / "jobs.json"));

  // A tasks folder that is a link to the user's folder.
  stdfs::create_directories(dir / "victim");
  writeTextFile(dir / "victim", "data.txt", "precious");
  stdfs::create_directories(dir / "r");
  stdfs::create_directory_symlink(dir / "victim", dir / "r" / "tasks");
  r = runPluvia({"farm", "slurm", plate, "-p", "moderate", "-o",
                 (dir / "b" / "r.####.png").string(), "--chunk", "2", "--farm-dir",
                 (dir / "r").string()});
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_TRUE(stdfs::exists(dir / "victim" / "data.txt"));

  // pluvia's own farm folder is rewritten: its old task records go, other files stay.
  const stdfs::path own = dir / "own";
  const std::vector<std::string> job = {"farm",
                                        "slurm",
                                        plate,
                                        "-p",
                                        "moderate",
                                        "-o",
                                        (dir / "c" / "r.####.png").string(),
                                        "--chunk",
                                        "2",
                                        "--farm-dir",
                                        own.string()};
  r = runPluvia(job);
  ASSERT_EQ(r.exitCode, 0) << r.output;
  writeTextFile(own / "tasks", "render-0.status", "1 host log");
  writeTextFile(own / "tasks", "notes.txt", "mine");
  r = runPluvia(job);
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_FALSE(stdfs::exists(own / "tasks" / "render-0.status"));
  EXPECT_TRUE(stdfs::exists(own / "tasks" / "notes.txt"));
}

// The chunks render what `render` would with the same options (one list of options for both
// commands), with the threads Slurm gives them, in the colour config the submitting shell had;
// a requeued task appends to its log.
TEST(CliFarmScripts, TheChunksGetTheRendersOptionsThreadsAndColourConfig) {
  const stdfs::path dir = freshTempDir("farm_options");
  const std::string plate = writeTexturedPlate(dir, 1, 4);
  const stdfs::path config = writeTextFile(dir, "facility.ocio", "ocio_profile_version: 2\n");
  const auto withOcio = runProcess({"env",
                                    "OCIO=" + config.string(),
                                    pluviaBinary().string(),
                                    "farm",
                                    "slurm",
                                    plate,
                                    "-p",
                                    "moderate",
                                    "-o",
                                    (dir / "a" / "o.####.exr").string(),
                                    "--chunk",
                                    "2",
                                    "--aov",
                                    "rain,matte",
                                    "--proxy",
                                    "0.5",
                                    "--exr-compression",
                                    "dwaa",
                                    "--cpus-per-task",
                                    "1"});
  ASSERT_EQ(withOcio.exitCode, 0) << withOcio.output;
  const std::string render = fs::readTextFile(dir / "a" / "o.farm" / "render.sbatch");
  for (const std::string& wanted :
       {std::string("--threads 1 --exr-compression dwaa --aov rain,matte --proxy 0.5"),
        "export OCIO=" + config.string(), std::string("#SBATCH --open-mode=append")})
    EXPECT_NE(render.find(wanted), std::string::npos) << wanted << "\n" << render;
  const std::string prepare = fs::readTextFile(dir / "a" / "o.farm" / "prepare.sbatch");
  EXPECT_NE(prepare.find("--proxy 0.5"), std::string::npos) << prepare;

  // No --cpus-per-task: each chunk takes its node's allocation. A movie's codec goes to the
  // assembly, not to the chunks' TIFF frames.
  auto r = runPluvia({"farm", "slurm", plate, "-p", "moderate", "-o",
                      (dir / "b" / "o.mov").string(), "--chunk", "2", "--codec", "prores_4444"});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const std::string chunks = fs::readTextFile(dir / "b" / "o.farm" / "render.sbatch");
  const std::string threads = "\"${SLURM_CPUS_PER_TASK:-${SLURM_CPUS_ON_NODE:-$(nproc)}}\"";
  EXPECT_NE(chunks.find("--threads " + threads), std::string::npos) << chunks;
  // What that expands to in each Slurm mode: --cpus-per-task, --exclusive (the node's CPUs
  // only), and no Slurm variable at all (the CPUs this process may use).
  const auto expand = [&](const std::string& environment) {
    return runProcess({"bash", "-c", environment + " printf %s " + threads}).output;
  };
  EXPECT_EQ(expand("SLURM_CPUS_PER_TASK=3; SLURM_CPUS_ON_NODE=16;"), "3");
  EXPECT_EQ(expand("unset SLURM_CPUS_PER_TASK; SLURM_CPUS_ON_NODE=16;"), "16");
  const std::string cpus = runProcess({"nproc"}).output;
  EXPECT_EQ(expand("unset SLURM_CPUS_PER_TASK SLURM_CPUS_ON_NODE;"),
            cpus.substr(0, cpus.find('\n')));
  EXPECT_EQ(chunks.find("prores"), std::string::npos) << chunks;
  const std::string assemble = fs::readTextFile(dir / "b" / "o.farm" / "assemble.sbatch");
  EXPECT_NE(assemble.find("--codec prores_4444"), std::string::npos) << assemble;

  // An option the render would refuse is refused here, before any script is written.
  r = runPluvia({"farm", "slurm", plate, "-p", "moderate", "-o",
                 (dir / "c" / "o.####.exr").string(), "--chunk", "2", "--aov", "rain,sparkle"});
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find("unknown output 'sparkle'"), std::string::npos) << r.output;
  EXPECT_FALSE(stdfs::exists(dir / "c" / "o.farm"));
  // A farm movie is assembled from the chunks' beauty frames: AOVs asked of it would be lost.
  r = runPluvia({"farm", "slurm", plate, "-p", "moderate", "-o", (dir / "d" / "o.mov").string(),
                 "--chunk", "2", "--codec", "prores_4444", "--aov", "rain"});
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find("without their AOVs"), std::string::npos) << r.output;
  EXPECT_FALSE(stdfs::exists(dir / "d" / "o.farm"));
}

// A task stopped at its job's time limit is told from a failure: Slurm sends the script USR1 a
// minute before the limit (#SBATCH --signal=B:USR1@60); the script stops the render (SIGTERM:
// it finishes its frame and writes no partial one) and records "timeout", which `farm status`
// shows as TIMEOUT and exits 3 for (1 for a failure). A resubmitted task renders only the rest.
TEST(CliFarmScripts, ATaskStoppedAtItsTimeLimitIsATimeOutNotAFailure) {
  const stdfs::path dir = freshTempDir("farm_timeout");
  const std::string plate = writeTexturedPlate(dir, 1, 60);
  const stdfs::path farm = dir / "f";
  auto r = runPluvia({"farm", "slurm", plate, "-p", "moderate", "-o",
                      (dir / "out" / "r.####.png").string(), "--chunk", "60", "--farm-dir",
                      farm.string(), "--cpus-per-task", "1"});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const std::string render = fs::readTextFile(farm / "render.sbatch");
  EXPECT_NE(render.find("#SBATCH --signal=B:USR1@60"), std::string::npos) << render;
  ASSERT_EQ(runScript(farm / "prepare.sbatch"), 0);
  // What Slurm does at the time limit, once the first frame is on disk.
  const ProcessResult stopped = runProcess(
      {"bash", "-c",
       "SLURM_ARRAY_TASK_ID=0 SLURM_ARRAY_JOB_ID=8 SLURM_JOB_ID=8 bash \"$1\" & task=$!\n"
       "until [ -e \"$2\" ]; do sleep 0.02; done\n"
       "kill -USR1 $task; wait $task",
       "-", (farm / "render.sbatch").string(), (dir / "out" / "r.0001.png").string()});
  EXPECT_EQ(stopped.exitCode, 143) << stopped.output;  // pluvia's exit on SIGTERM
  const std::string record = fs::readTextFile(farm / "tasks" / "render-0.status");
  EXPECT_NE(record.find(" timeout"), std::string::npos) << record;
  EXPECT_FALSE(stdfs::exists(dir / "out" / "r.0060.png"));

  fs::writeTextFile(farm / "jobs.json", R"({"prepare": "7", "render": "8", "assemble": ""})");
  r = runPluvia({"farm", "status", farm.string()});
  EXPECT_EQ(r.exitCode, 3) << r.output;
  EXPECT_NE(r.output.find("TIMEOUT (stopped at the job's time limit, exit 143)"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("timed out (1;"), std::string::npos) << r.output;

  // A failure is still a failure.
  fs::writeTextFile(farm / "tasks" / "render-0.status", "1 node1 exit /logs/render-8_0.log\n");
  r = runPluvia({"farm", "status", farm.string()});
  EXPECT_EQ(r.exitCode, 1) << r.output;
  EXPECT_NE(r.output.find("FAILED (exit 1)"), std::string::npos) << r.output;

  // Resubmitted, the task renders the frames the time-out left and completes.
  ASSERT_EQ(runProcess({"env", "SLURM_ARRAY_TASK_ID=0", "SLURM_ARRAY_JOB_ID=9", "SLURM_JOB_ID=9",
                        "bash", (farm / "render.sbatch").string()})
                .exitCode,
            0);
  EXPECT_TRUE(stdfs::exists(dir / "out" / "r.0060.png"));
  r = runPluvia({"farm", "status", farm.string()});
  EXPECT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("all done"), std::string::npos) << r.output;
}

// The movie a farm job assembles carries the plate's timecode and colour as the same render on
// one machine does: a ProRes plate tagged BT.709 at 01:00:10:00, frames 2-5, gives a movie
// tagged BT.709 starting at 01:00:10:02 either way.
TEST(CliFarmScripts, TheAssembledMovieCarriesThePlatesTimecodeAndColourTags) {
  const stdfs::path dir = freshTempDir("farm_timecode");
  const stdfs::path plate = dir / "plate.mov";
  ASSERT_EQ(runProcess({"ffmpeg",
                        "-v",
                        "error",
                        "-f",
                        "lavfi",
                        "-i",
                        "testsrc=size=96x64:rate=24",
                        "-frames:v",
                        "6",
                        "-c:v",
                        "prores_ks",
                        "-profile:v",
                        "hq",
                        "-pix_fmt",
                        "yuv422p10le",
                        "-vf",
                        "setparams=color_primaries=bt709:color_trc=bt709:colorspace=bt709",
                        "-timecode",
                        "01:00:10:00",
                        plate.string()})
                .exitCode,
            0);
  const stdfs::path farm = dir / "f";
  auto r = runPluvia({"farm", "slurm", plate.string(), "-p", "drizzle", "-o",
                      (dir / "farm.mov").string(), "--chunk", "2", "--frames", "2-5", "--farm-dir",
                      farm.string(), "--codec", "prores_422hq"});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const std::string assemble = fs::readTextFile(farm / "assemble.sbatch");
  EXPECT_NE(assemble.find("--timecode 01:00:10:02 --colorspace rec709"), std::string::npos)
      << assemble;
  ASSERT_EQ(runScript(farm / "prepare.sbatch"), 0);
  for (const char* task : {"0", "1"})
    ASSERT_EQ(runProcess({"env", std::string("SLURM_ARRAY_TASK_ID=") + task, "SLURM_JOB_ID=7",
                          "bash", (farm / "render.sbatch").string()})
                  .exitCode,
              0);
  ASSERT_EQ(runScript(farm / "assemble.sbatch"), 0);
  r = runPluvia({"render", plate.string(), "-p", "drizzle", "-o", (dir / "local.mov").string(),
                 "--frames", "2-5", "--codec", "prores_422hq"});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  for (const char* movie : {"farm.mov", "local.mov"}) {
    const ProcessResult probe = runProcess(
        {"ffprobe", "-v", "error", "-show_entries",
         "stream=color_transfer,color_primaries:stream_tags=timecode:format_tags=timecode", "-of",
         "default=nw=1", (dir / movie).string()});
    EXPECT_NE(probe.output.find("timecode=01:00:10:02"), std::string::npos)
        << movie << ": " << probe.output;
    EXPECT_NE(probe.output.find("color_transfer=bt709"), std::string::npos)
        << movie << ": " << probe.output;
  }
}
