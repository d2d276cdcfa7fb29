// `pluvia farm status` reads what others may have edited or damaged: a farm.json whose chunk
// size is 0 or whose frame range makes billions of chunks is refused, naming the file and the
// key (it crashed with SIGFPE, or ran for ever), and a task record that is not what the job's
// script writes is UNREADABLE and failed, not COMPLETED. No scheduler is needed: the jobs were
// never submitted, and a record decides a task's state once it is out of the queue.
#include <gtest/gtest.h>

#include <fstream>
#include <regex>

#include "test_support.h"
#include "util/fs.h"

using namespace pluvia::test;
namespace stdfs = std::filesystem;

namespace {

// A farm folder for the 6-frame example cut, as `farm slurm` writes it, with job ids recorded as
// if it had been submitted.
stdfs::path farmFolder(const stdfs::path& dir, int chunk) {
  const stdfs::path farm = dir / "farm";
  const auto made = runPluvia({"-q", "farm", "slurm", exampleClip().string(), "-p", "moderate",
                               "-o", (dir / "out" / "r.####.png").string(), "--frames", "0-5",
                               "--chunk", std::to_string(chunk), "--farm-dir", farm.string()});
  EXPECT_EQ(made.exitCode, 0) << made.output;
  std::ofstream(farm / "jobs.json") << R"({"prepare":"1","render":"2","assemble":""})";
  return farm;
}

void replaceInFile(const stdfs::path& path, const std::regex& what, const std::string& with) {
  const std::string text = pluvia::fs::readTextFile(path);
  std::ofstream(path) << std::regex_replace(text, what, with);
}

}  // namespace

TEST(CliFarmRecords, ABrokenFarmJsonIsRefusedNamingTheKey) {
  const stdfs::path dir = freshTempDir("farm_records_json");
  const stdfs::path farm = farmFolder(dir, 2);
  replaceInFile(farm / "farm.json", std::regex(R"("chunk_frames": 2)"), R"("chunk_frames": 0)");
  const auto zero = runPluvia({"farm", "status", farm.string()});
  EXPECT_EQ(zero.exitCode, 1) << zero.output;
  EXPECT_NE(zero.output.find("farm.json: chunk_frames is 0"), std::string::npos) << zero.output;

  replaceInFile(farm / "farm.json", std::regex(R"("chunk_frames": 0)"), R"("chunk_frames": 1)");
  replaceInFile(farm / "farm.json", std::regex(R"("last_frame": 5)"),
                R"("last_frame": 2000000000)");
  const auto huge = runPluvia({"farm", "status", farm.string()});
  EXPECT_EQ(huge.exitCode, 1) << huge.output;
  EXPECT_NE(huge.output.find("farm.json: last_frame 2000000000 makes"), std::string::npos)
      << huge.output;

  // Numbers an int64_t cannot hold, or that are no integer, are refused, not wrapped.
  replaceInFile(farm / "farm.json", std::regex(R"("last_frame": 2000000000)"),
                R"("last_frame": 5)");
  replaceInFile(farm / "farm.json", std::regex(R"("chunk_frames": 1)"), R"("chunk_frames": 1e300)");
  const auto wide = runPluvia({"farm", "status", farm.string()});
  EXPECT_EQ(wide.exitCode, 1) << wide.output;
  EXPECT_NE(wide.output.find("farm.json: chunk_frames is 1e+300; it must be an integer"),
            std::string::npos)
      << wide.output;
  replaceInFile(farm / "farm.json", std::regex(R"("chunk_frames": 1e\+?300)"),
                R"("chunk_frames": 1)");
  replaceInFile(farm / "farm.json", std::regex(R"("first_frame": 0)"),
                R"("first_frame": -9223372036854775808)");
  const auto low = runPluvia({"farm", "status", farm.string()});
  EXPECT_EQ(low.exitCode, 1) << low.output;
  EXPECT_NE(low.output.find("first_frame is -9223372036854775808; it must be an integer"),
            std::string::npos)
      << low.output;
}

TEST(CliFarmRecords, AGarbledTaskRecordIsAFailureNotACompletion) {
  const stdfs::path dir = freshTempDir("farm_records_task");
  const stdfs::path farm = farmFolder(dir, 6);
  std::ofstream(farm / "tasks" / "prepare.status") << "0 host prepare.log\n";
  std::ofstream(farm / "tasks" / "render-0.status") << "garbage\n";
  const auto status = runPluvia({"farm", "status", farm.string()});
  EXPECT_NE(status.exitCode, 0) << status.output;
  EXPECT_NE(status.output.find("2_0"), std::string::npos) << status.output;
  EXPECT_NE(status.output.find("UNREADABLE task record"), std::string::npos) << status.output;
  EXPECT_NE(status.output.find("reads 'garbage?'"), std::string::npos) << status.output;
  EXPECT_EQ(status.output.find("2_0        frames 0-5   COMPLETED"), std::string::npos)
      << status.output;
}
