#include "util/fs.h"

#include <unistd.h>

#include <atomic>
#include <fstream>
#include <sstream>

#include "util/error.h"

namespace pluvia::fs {
namespace stdfs = std::filesystem;

stdfs::path temporaryPathFor(const stdfs::path& target) {
  static std::atomic<uint64_t> counter{0};
  stdfs::path tmp = target.parent_path() /
                    (target.stem().string() + ".pluvia-tmp-" + std::to_string(getpid()) + "-" +
                     std::to_string(counter++) + target.extension().string());
  return tmp;
}

void commitTemporary(const stdfs::path& tmp, const stdfs::path& target) {
  std::error_code ec;
  stdfs::rename(tmp, target, ec);
  if (ec) {
    stdfs::remove(tmp, ec);
    throw Error("cannot move the finished file into place: " + ec.message(), {"write", {}, target.string()});
  }
}

void ensureParentFolder(const stdfs::path& file) {
  stdfs::path folder = file.parent_path();
  if (folder.empty()) return;
  std::error_code ec;
  stdfs::create_directories(folder, ec);
  if (ec) throw Error("cannot create output folder " + folder.string() + ": " + ec.message(), {"write", {}, folder.string()});
  if (access(folder.c_str(), W_OK) != 0) {
    throw Error("output folder " + folder.string() + " is not writable", {"write", {}, folder.string()});
  }
}

bool samePath(const stdfs::path& a, const stdfs::path& b) {
  std::error_code ec;
  if (stdfs::exists(a, ec) && stdfs::exists(b, ec)) return stdfs::equivalent(a, b, ec);
  return stdfs::weakly_canonical(a, ec) == stdfs::weakly_canonical(b, ec);
}

std::string readTextFile(const stdfs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot open " + path.string(), {{}, {}, path.string()});
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

void writeTextFile(const stdfs::path& path, const std::string& text) {
  ensureParentFolder(path);
  stdfs::path tmp = temporaryPathFor(path);
  {
    std::ofstream out(tmp, std::ios::binary);
    out << text;
    if (!out) {
      std::error_code ec;
      stdfs::remove(tmp, ec);
      throw Error("cannot write " + path.string(), {{}, {}, path.string()});
    }
  }
  commitTemporary(tmp, path);
}

}  // namespace pluvia::fs
