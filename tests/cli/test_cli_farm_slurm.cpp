// `pluvia farm slurm` on a throw-away single-node Slurm cluster started in a temp folder (its
// own munged, slurm.conf, state, ports): a 24-frame clip in 4 chunks gives frames byte-identical
// to a one-machine render, a movie assembled after its chunks is the one-machine movie, and a
// failed chunk is listed with its log. Skipped where the cluster cannot start (no Slurm or munge
// installed, not root, a container that forbids it).
// ctest: one process (the suite's set-up runs once for all its tests)
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <fstream>
#include <regex>
#include <thread>

#include "test_support.h"
#include "util/fs.h"
#include "util/subprocess.h"

using namespace pluvia;
using namespace pluvia::test;
namespace stdfs = std::filesystem;

namespace {

// The CPUs the throw-away node says it has (ExclusiveChunksTakeTheNodesThreads).
constexpr int kNodeCpus = 3;

// A TCP port nothing listens on now.
int freePort() {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t size = sizeof address;
  int port = 0;
  if (bind(fd, reinterpret_cast<sockaddr*>(&address), size) == 0 &&
      getsockname(fd, reinterpret_cast<sockaddr*>(&address), &size) == 0)
    port = ntohs(address.sin_port);
  close(fd);
  return port;
}

std::string tail(const stdfs::path& path) {
  if (!stdfs::exists(path)) return path.string() + ": absent\n";
  const std::string text = fs::readTextFile(path);
  return path.string() + ":\n" + text.substr(text.size() > 1500 ? text.size() - 1500 : 0);
}

// munged, slurmctld and slurmd for one test, on ports of their own, with every file in `dir`;
// SLURM_CONF points the test's processes (and so sbatch, squeue and the jobs) at it. Stopped by
// the destructor, whatever the test did.
class ThrowAwayCluster {
 public:
  explicit ThrowAwayCluster(const stdfs::path& dir) : dir_(dir) {}
  ~ThrowAwayCluster() { stop(); }

  // "" once the node is idle, else why the cluster could not start.
  std::string start() {
    if (geteuid() != 0) return "not root (slurmd runs jobs as root here)";
    for (const char* program : {"munged", "slurmctld", "slurmd", "sbatch", "squeue", "sinfo"})
      if (!programAvailable(program)) return std::string(program) + " is not installed";
    for (const char* sub : {"munge", "state", "spool", "log"})
      stdfs::create_directories(dir_ / sub);
    stdfs::permissions(dir_ / "munge", stdfs::perms::owner_all);
    {
      std::ifstream random("/dev/urandom", std::ios::binary);
      std::string key(1024, '\0');
      random.read(key.data(), static_cast<std::streamsize>(key.size()));
      std::ofstream(dir_ / "munge" / "munge.key", std::ios::binary) << key;
    }
    stdfs::permissions(dir_ / "munge" / "munge.key", stdfs::perms::owner_read);
    const std::string socket = (dir_ / "munge" / "munge.socket").string();
    const ProcessResult munged =
        runProcess({"munged", "--force", "--socket=" + socket,
                    "--key-file=" + (dir_ / "munge" / "munge.key").string(),
                    "--log-file=" + (dir_ / "log" / "munged.log").string(),
                    "--pid-file=" + (dir_ / "munged.pid").string(),
                    "--seed-file=" + (dir_ / "munge" / "munged.seed").string()});
    if (munged.exitCode != 0) return "munged did not start: " + munged.output;

    char host[256] = {};
    gethostname(host, sizeof host - 1);
    std::string shortHost = host;
    shortHost = shortHost.substr(0, shortHost.find('.'));
    const std::string d = dir_.string();
    // No systemd or cgroups (PLATFORM.md): linuxproc tracking, no task plugin, no accounting.
    std::ofstream(dir_ / "slurm.conf")
        << "ClusterName=pluviatest\n"
        << "SlurmctldHost=" << shortHost << "(127.0.0.1)\n"
        << "SlurmctldPort=" << freePort() << "\n"
        << "SlurmdPort=" << freePort() << "\n"
        << "SlurmUser=root\nSlurmdUser=root\n"
        << "AuthType=auth/munge\nCredType=cred/munge\n"
        << "AuthInfo=socket=" << socket << "\n"
        << "StateSaveLocation=" << d << "/state\n"
        << "SlurmdSpoolDir=" << d << "/spool\n"
        << "SlurmctldPidFile=" << d << "/slurmctld.pid\n"
        << "SlurmdPidFile=" << d << "/slurmd.pid\n"
        << "SlurmctldLogFile=" << d << "/log/slurmctld.log\n"
        << "SlurmdLogFile=" << d << "/log/slurmd.log\n"
        << "ProctrackType=proctrack/linuxproc\n"
        << "TaskPlugin=task/none\n"
        << "JobAcctGatherType=jobacct_gather/none\n"
        << "AccountingStorageType=accounting_storage/none\n"
        << "SelectType=select/cons_tres\n"
        << "SelectTypeParameters=CR_CPU\n"
        << "MpiDefault=none\nReturnToService=2\n"
        << "MinJobAge=600\nKillWait=5\n"
        // The node says it has more CPUs than the machine (slurmd takes the configured count),
        // so that a chunk's thread count from the allocation differs from the old default of 2
        // even on a 2-core machine.
        << "SlurmdParameters=config_overrides\n"
        << "NodeName=pluvianode NodeHostname=" << shortHost
        << " NodeAddr=127.0.0.1 CPUs=" << kNodeCpus << "\n"
        << "PartitionName=pluvia Nodes=pluvianode Default=YES "
           "MaxTime=INFINITE State=UP\n";
    setenv("SLURM_CONF", (dir_ / "slurm.conf").c_str(), 1);
    const ProcessResult ctld = runProcess({"slurmctld", "-i"});
    if (ctld.exitCode != 0)
      return "slurmctld did not start: " + ctld.output + tail(dir_ / "log" / "slurmctld.log");
    started_ = true;
    const ProcessResult slurmd = runProcess({"slurmd", "-N", "pluvianode"});
    if (slurmd.exitCode != 0)
      return "slurmd did not start: " + slurmd.output + tail(dir_ / "log" / "slurmd.log");
    const bool idle = waitUntil(
        [] {
          const ProcessResult r = runProcess({"sinfo", "-h", "-o", "%T"});
          return r.exitCode == 0 && r.output.find("idle") != std::string::npos;
        },
        30);
    if (!idle)
      return "the node did not come up idle:\n" + tail(dir_ / "log" / "slurmctld.log") +
             tail(dir_ / "log" / "slurmd.log");
    return "";
  }

  std::string logs() const {
    return tail(dir_ / "log" / "slurmctld.log") + tail(dir_ / "log" / "slurmd.log");
  }

 private:
  void killFromPidFile(const stdfs::path& pidFile) {
    if (!stdfs::exists(pidFile)) return;
    std::ifstream in(pidFile);
    pid_t pid = 0;
    if (!(in >> pid) || pid <= 1) return;
    kill(pid, SIGTERM);
    for (int i = 0; i < 50 && kill(pid, 0) == 0; ++i)
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    if (kill(pid, 0) == 0) kill(pid, SIGKILL);
  }

  void stop() {
    if (started_) runProcess({"scontrol", "shutdown"});
    killFromPidFile(dir_ / "slurmd.pid");
    killFromPidFile(dir_ / "slurmctld.pid");
    killFromPidFile(dir_ / "munged.pid");
    unsetenv("SLURM_CONF");
  }

  stdfs::path dir_;
  bool started_ = false;
};

// 24 frames, 1001-1024, of a small plate with a bright sky over a darker, textured ground.
std::string writePlate(const stdfs::path& dir) {
  constexpr int kWidth = 96, kHeight = 64, kSkyRows = kHeight / 3;
  return writePixelPlate(dir, 1001, 1024, kWidth, kHeight, [](float* p, int x, int y, int frame) {
    const float ground = 0.15f + 0.1f * float((x * 3 + y * 5 + frame) % 11) / 10.0f;
    p[0] = y < kSkyRows ? 0.85f : ground;
    p[1] = y < kSkyRows ? 0.9f : ground;
    p[2] = y < kSkyRows ? 0.95f : ground * 0.8f;
  });
}

double secondsOf(const std::function<void()>& work) {
  const auto start = std::chrono::steady_clock::now();
  work();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::string frameName(int frame) {
  char name[32];
  std::snprintf(name, sizeof name, "o.%04d.png", frame);
  return name;
}

// The job ids `pluvia farm slurm --submit` printed.
std::vector<std::string> jobIds(const std::string& output) {
  std::vector<std::string> ids;
  const std::regex job(R"((prepare job|render job array|assemble job) (\d+))");
  for (std::sregex_iterator it(output.begin(), output.end(), job), end; it != end; ++it)
    ids.push_back((*it)[2]);
  return ids;
}

}  // namespace

// One cluster for the suite (starting one takes seconds); each test its own folders.
class FarmSlurm : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    clusterDir_ = freshTempDir("farm_slurm_cluster");
    cluster_ = new ThrowAwayCluster(clusterDir_);
    whyNot_ = cluster_->start();
  }
  static void TearDownTestSuite() {
    delete cluster_;
    cluster_ = nullptr;
  }
  void SetUp() override {
    if (!whyNot_.empty()) GTEST_SKIP() << "no throw-away Slurm cluster here: " << whyNot_;
    dir_ = freshTempDir(::testing::UnitTest::GetInstance()->current_test_info()->name());
    stdfs::create_directories(dir_ / "plate");
    plate_ = writePlate(dir_ / "plate");
  }

  // `pluvia farm slurm` of the plate into dir_/farm/OUTPUT in chunks of 6 frames, submitted.
  CommandResult submit(const std::string& output,
                       const std::vector<std::string>& options = {}) const {
    std::vector<std::string> args = {
        "farm",    "slurm", plate_,    "-p", "drizzle", "-o", (dir_ / "farm" / output).string(),
        "--chunk", "6",     "--submit"};
    args.insert(args.end(), options.begin(), options.end());
    return runPluvia(args);
  }
  // `pluvia farm status` of dir_/farm/FARM, waiting for its jobs (up to 120 s).
  CommandResult waitForFarm(const std::string& farm) const {
    return runPluvia(
        {"farm", "status", (dir_ / "farm" / farm).string(), "--wait", "--timeout", "120"});
  }

  static inline stdfs::path clusterDir_;
  static inline ThrowAwayCluster* cluster_ = nullptr;
  static inline std::string whyNot_;
  stdfs::path dir_;
  std::string plate_;
};

TEST_F(FarmSlurm, FourChunksGiveTheOneMachineFramesByteForByte) {
  CommandResult one;
  const double oneSeconds = secondsOf([&] {
    one =
        runPluvia({"render", plate_, "-p", "drizzle", "-o", (dir_ / "one" / "o.####.png").string(),
                   "--cache", (dir_ / "one-cache").string()});
  });
  ASSERT_EQ(one.exitCode, 0) << one.output;

  CommandResult submitted, status;
  const stdfs::path farmDir = dir_ / "farm" / "o.farm";
  const double farmSeconds = secondsOf([&] {
    submitted = submit("o.####.png");
    if (submitted.exitCode == 0) status = waitForFarm("o.farm");
  });
  ASSERT_EQ(submitted.exitCode, 0) << submitted.output;
  const std::vector<std::string> ids = jobIds(submitted.output);
  ASSERT_EQ(ids.size(), 2u) << submitted.output;
  EXPECT_NE(
      submitted.output.find("render job array " + ids[1] + " (4 tasks, after " + ids[0] + ")"),
      std::string::npos)
      << submitted.output;
  ASSERT_EQ(status.exitCode, 0) << status.output << cluster_->logs();
  EXPECT_NE(status.output.find("all done"), std::string::npos) << status.output;
  for (const char* task : {"_0 ", "_1 ", "_2 ", "_3 "})
    EXPECT_NE(status.output.find(ids[1] + task), std::string::npos) << status.output;
  EXPECT_NE(status.output.find("frames 1019-1024 COMPLETED"), std::string::npos) << status.output;

  for (int f = 1001; f <= 1024; ++f) {
    const stdfs::path a = dir_ / "one" / frameName(f), b = dir_ / "farm" / frameName(f);
    ASSERT_TRUE(stdfs::exists(b)) << b << "\n" << status.output;
    EXPECT_EQ(fs::readTextFile(a), fs::readTextFile(b)) << frameName(f) << " differs";
  }
  // The chunks only read the cache the prepare job filled.
  for (int task = 0; task < 4; ++task) {
    const std::string log = fs::readTextFile(
        farmDir / "logs" / ("render-" + ids[1] + "_" + std::to_string(task) + ".log"));
    EXPECT_NE(log.find("lighting: from the plate, from cache"), std::string::npos) << log;
  }
  // For the issue's note: the job ids, the status and the timing.
  std::cout << "job ids: prepare " << ids[0] << ", render array " << ids[1] << "\n"
            << "pluvia farm status printed:\n"
            << status.output << "one machine: " << oneSeconds
            << " s; 4 chunks through Slurm (submission to the last task's end): " << farmSeconds
            << " s\n";
}

TEST_F(FarmSlurm, AMovieIsAssembledAfterItsChunksAsTheOneMachineMovie) {
  // ProRes 4444: the codec goes to the assembly job (the chunks write TIFF).
  const auto one = runPluvia({"render", plate_, "-p", "drizzle", "-o", (dir_ / "one.mov").string(),
                              "--codec", "prores_4444"});
  ASSERT_EQ(one.exitCode, 0) << one.output;
  const auto submitted = submit("rain.mov", {"--codec", "prores_4444"});
  ASSERT_EQ(submitted.exitCode, 0) << submitted.output;
  const std::vector<std::string> ids = jobIds(submitted.output);
  ASSERT_EQ(ids.size(), 3u) << submitted.output;
  EXPECT_NE(submitted.output.find("assemble job " + ids[2] + " (after " + ids[1] + ")"),
            std::string::npos);
  const auto status = waitForFarm("rain.farm");
  ASSERT_EQ(status.exitCode, 0) << status.output << cluster_->logs();
  EXPECT_NE(status.output.find("assemble  " + ids[2]), std::string::npos) << status.output;
  // The chunks wrote float frames, which the movie writer takes as it takes a render's frames:
  // the same samples, so the same movie.
  ASSERT_TRUE(stdfs::exists(dir_ / "farm" / "rain.mov")) << status.output;
  EXPECT_EQ(fs::readTextFile(dir_ / "one.mov"), fs::readTextFile(dir_ / "farm" / "rain.mov"));
  const stdfs::path chunkFrame = dir_ / "farm" / "rain.farm" / "frames" / "rain.1024.tif";
  ASSERT_TRUE(stdfs::exists(chunkFrame));
  auto frame = OIIO::ImageInput::open(chunkFrame.string());
  ASSERT_TRUE(frame);
  EXPECT_EQ(frame->spec().format, OIIO::TypeDesc::FLOAT) << "a 16-bit frame clips super-whites";
}

// Every option of `render` reaches the chunks through a farm folder whose path holds a space:
// the frames are the one-machine ones (a movie's codec: the test above).
TEST_F(FarmSlurm, EveryRenderOptionReachesTheChunksThroughAPathWithASpace) {
  const std::vector<std::string> options = {"--aov", "rain,matte,depth",  "--proxy",
                                            "0.5",   "--exr-compression", "dwaa"};
  std::vector<std::string> local = {"render",  plate_, "-p",
                                    "drizzle", "-o",   (dir_ / "one" / "o.####.exr").string()};
  local.insert(local.end(), options.begin(), options.end());
  const auto one = runPluvia(local);
  ASSERT_EQ(one.exitCode, 0) << one.output;
  const stdfs::path spaced = dir_ / "my shots";
  std::vector<std::string> farm = {
      "farm",    "slurm", plate_,    "-p", "drizzle", "-o", (spaced / "o.####.exr").string(),
      "--chunk", "12",    "--submit"};
  farm.insert(farm.end(), options.begin(), options.end());
  const auto submitted = runPluvia(farm);
  ASSERT_EQ(submitted.exitCode, 0) << submitted.output;
  const auto status =
      runPluvia({"farm", "status", (spaced / "o.farm").string(), "--wait", "--timeout", "120"});
  ASSERT_EQ(status.exitCode, 0) << status.output << cluster_->logs();
  for (int f = 1001; f <= 1024; ++f) {
    const std::string name = "o." + std::to_string(f) + ".exr";
    ASSERT_TRUE(stdfs::exists(spaced / name)) << name << "\n" << status.output;
    EXPECT_EQ(fs::readTextFile(dir_ / "one" / name), fs::readTextFile(spaced / name))
        << name << " differs";
  }
}

TEST_F(FarmSlurm, AFailedChunkIsListedWithItsFramesAndLog) {
  // Frame 1014's file cannot be written: a folder stands at its name (a usage error, exit 2).
  stdfs::create_directories(dir_ / "farm" / frameName(1014));
  const auto submitted = submit("o.####.png");
  ASSERT_EQ(submitted.exitCode, 0) << submitted.output;
  const std::vector<std::string> ids = jobIds(submitted.output);
  ASSERT_EQ(ids.size(), 2u) << submitted.output;
  const auto status = waitForFarm("o.farm");
  EXPECT_EQ(status.exitCode, 1) << status.output << cluster_->logs();
  const std::string log =
      (dir_ / "farm" / "o.farm" / "logs" / ("render-" + ids[1] + "_2.log")).string();
  EXPECT_NE(status.output.find("failed (1):\n  render " + ids[1] +
                               "_2 frames 1013-1018: FAILED (exit 2), on "),
            std::string::npos)
      << status.output;
  EXPECT_NE(status.output.find("log " + log), std::string::npos) << status.output;
  EXPECT_NE(fs::readTextFile(log).find(frameName(1014)), std::string::npos)
      << fs::readTextFile(log);
  // The other chunks finished their frames.
  EXPECT_TRUE(stdfs::exists(dir_ / "farm" / frameName(1024)));

  // Its cause gone, `farm resubmit` runs that chunk alone again, and the job ends done.
  stdfs::remove_all(dir_ / "farm" / frameName(1014));
  const std::string farm = (dir_ / "farm" / "o.farm").string();
  const auto again = runPluvia({"farm", "resubmit", farm});
  ASSERT_EQ(again.exitCode, 0) << again.output;
  expectOutputHas(again.output, {"resubmitted render ", " (chunks 2)"});
  const auto done = waitForFarm("o.farm");
  EXPECT_EQ(done.exitCode, 0) << done.output << cluster_->logs();
  expectOutputHas(done.output, {"all done"});
  EXPECT_TRUE(stdfs::is_regular_file(dir_ / "farm" / frameName(1014)));
  expectOutputHas(runPluvia({"farm", "resubmit", farm}).output, {"nothing to resubmit"});
}

// A whole-node allocation sets no SLURM_CPUS_PER_TASK: each chunk still takes the node's CPUs
// (SLURM_CPUS_ON_NODE), and its log says how many.
TEST_F(FarmSlurm, ExclusiveChunksTakeTheNodesThreads) {
  const auto submitted = submit("o.####.png", {"--sbatch-arg=--exclusive"});
  ASSERT_EQ(submitted.exitCode, 0) << submitted.output;
  const std::vector<std::string> ids = jobIds(submitted.output);
  ASSERT_EQ(ids.size(), 2u) << submitted.output;
  const auto status = waitForFarm("o.farm");
  ASSERT_EQ(status.exitCode, 0) << status.output << cluster_->logs();
  const std::string log =
      fs::readTextFile(dir_ / "farm" / "o.farm" / "logs" / ("render-" + ids[1] + "_0.log"));
  EXPECT_NE(log.find("threads: " + std::to_string(kNodeCpus)), std::string::npos) << log;
}
