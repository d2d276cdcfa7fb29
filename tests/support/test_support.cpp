#include "test_support.h"

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <sstream>
#include <thread>
#include <typeinfo>

#include <gtest/gtest.h>
#include "util/subprocess.h"

namespace pluvia::test {
namespace stdfs = std::filesystem;

stdfs::path sourceDir() {
  return PLUVIA_SOURCE_DIR;
}
stdfs::path pluviaBinary() {
  return PLUVIA_BINARY_PATH;
}
stdfs::path exampleClip() {
  return sourceDir() / "examples/street/street_plate.mp4";
}

stdfs::path sharedData() {
  if (const char* env = std::getenv("PLUVIA_SHARED_DATA")) {
    if (stdfs::is_directory(env)) return env;
  }
  stdfs::path beside = sourceDir().parent_path() / "shared" / "data";
  if (stdfs::is_directory(beside)) return beside;
  return {};
}

namespace {
stdfs::path processTempDir() {
  return stdfs::temp_directory_path() / ("pluvia-test-" + std::to_string(::getpid()));
}

// A test process's folders go once its tests have all passed: the suite runs some 750
// processes, and each one's folder (up to tens of MB) would otherwise stay in the temporary
// folder after every run. A failed test's are kept to look at.
class RemoveTempDirWhenPassed : public ::testing::Environment {
 public:
  void TearDown() override {
    if (!::testing::UnitTest::GetInstance()->Passed()) return;
    std::error_code ignored;
    stdfs::remove_all(processTempDir(), ignored);
  }
};
[[maybe_unused]] const ::testing::Environment* const kRemoveTempDir =
    ::testing::AddGlobalTestEnvironment(new RemoveTempDirWhenPassed);
}  // namespace

stdfs::path freshTempDir(const std::string& name) {
  stdfs::path dir = processTempDir() / name;
  stdfs::remove_all(dir);
  stdfs::create_directories(dir);
  return dir;
}

CommandResult runPluvia(const std::vector<std::string>& args) {
  std::vector<std::string> argv{pluviaBinary().string()};
  argv.insert(argv.end(), args.begin(), args.end());
  ProcessResult r = runProcess(argv);
  return {r.exitCode, r.output};
}

int startPluvia(const std::vector<std::string>& args, const stdfs::path& log) {
  std::vector<std::string> argv{pluviaBinary().string()};
  argv.insert(argv.end(), args.begin(), args.end());
  std::vector<char*> pointers;
  for (std::string& a : argv) pointers.push_back(a.data());
  pointers.push_back(nullptr);
  const pid_t pid = fork();
  if (pid == 0) {
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(fd, 1);
    dup2(fd, 2);
    execv(pointers[0], pointers.data());
    _exit(127);
  }
  return pid;
}

int waitForExit(int pid) {
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 1000 + WTERMSIG(status);
}

bool waitUntil(const std::function<bool()>& ready, double seconds) {
  for (int i = 0; i < static_cast<int>(seconds * 10); ++i) {
    if (ready()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  return ready();
}

ExrPixels readAllChannels(const stdfs::path& path) {
  ExrPixels pixels;
  auto in = OIIO::ImageInput::open(path.string());
  if (!in) {
    ADD_FAILURE() << "cannot read " << path << ": " << OIIO::geterror();
    return pixels;
  }
  const OIIO::ImageSpec& spec = in->spec();
  pixels.channels = spec.channelnames;
  pixels.samples.resize(spec.image_pixels() * size_t(spec.nchannels));
  EXPECT_TRUE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, pixels.samples.data()))
      << in->geterror();
  return pixels;
}

double channelSum(const ExrPixels& pixels, const std::string& name) {
  const auto found = std::find(pixels.channels.begin(), pixels.channels.end(), name);
  if (found == pixels.channels.end()) return -1.0;
  const size_t c = size_t(found - pixels.channels.begin()), n = pixels.channels.size();
  double sum = 0.0;
  for (size_t i = c; i < pixels.samples.size(); i += n) sum += pixels.samples[i];
  return sum;
}

Image flatImage(int width, int height, float r, float g, float b) {
  Image image(width, height);
  for (size_t i = 0; i < image.pixelCount(); ++i) {
    image.rgba[i * 4 + 0] = r;
    image.rgba[i * 4 + 1] = g;
    image.rgba[i * 4 + 2] = b;
  }
  return image;
}

Image readImageFile(const stdfs::path& path) {
  OIIO::ImageBuf buf(path.string());
  if (!buf.read(0, 0, true, OIIO::TypeDesc::FLOAT))
    throw std::runtime_error("cannot read " + path.string());
  const auto& spec = buf.spec();
  Image image(spec.width, spec.height);
  std::vector<float> pixels(image.pixelCount() * spec.nchannels);
  buf.get_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, pixels.data());
  // Alpha is the channel named so (an RGB beauty followed by AOV channels has none: 1); grey
  // fills R, G and B.
  // (OpenImageIO's alpha_channel may be an AOV's "rain.A".)
  const auto named = std::find(spec.channelnames.begin(), spec.channelnames.end(), "A");
  const int alpha = spec.nchannels == 2                ? 1
                    : named != spec.channelnames.end() ? int(named - spec.channelnames.begin())
                                                       : -1;
  for (size_t i = 0; i < image.pixelCount(); ++i) {
    for (int c = 0; c < 3; ++c) {
      const int src = c < spec.nchannels && c != alpha ? c : 0;
      image.rgba[i * 4 + c] = pixels[i * spec.nchannels + src];
    }
    image.rgba[i * 4 + 3] = alpha >= 0 ? pixels[i * spec.nchannels + alpha] : 1.0f;
  }
  return image;
}

void writeImageFile(const stdfs::path& path, const Image& image, int channels) {
  OIIO::ImageSpec spec(image.width, image.height, channels, OIIO::TypeDesc::FLOAT);
  OIIO::ImageBuf buf(spec);
  std::vector<float> pixels(image.pixelCount() * channels);
  for (size_t i = 0; i < image.pixelCount(); ++i)
    for (int c = 0; c < channels; ++c) pixels[i * channels + c] = image.rgba[i * 4 + c];
  buf.set_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, pixels.data());
  if (!buf.write(path.string())) throw std::runtime_error("cannot write " + path.string());
}

int countLinesStartingWith(const std::string& text, const std::set<std::string>& firstWords) {
  std::istringstream lines(text);
  int count = 0;
  for (std::string line; std::getline(lines, line);) {
    std::istringstream words(line);
    std::string first;
    words >> first;
    count += firstWords.count(first) ? 1 : 0;
  }
  return count;
}

std::vector<std::string> splitCsv(const std::string& line) {
  std::vector<std::string> fields(1);
  bool quoted = false;
  for (char ch : line) {
    if (ch == '"') {
      quoted = !quoted;
    } else if (ch == ',' && !quoted) {
      fields.emplace_back();
    } else {
      fields.back() += ch;
    }
  }
  return fields;
}

double parseNumber(const std::string& text, const std::string& line) {
  size_t used = 0;
  double value = NAN;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
  }
  EXPECT_EQ(used, text.size()) << "'" << text << "' in: " << line;
  return value;
}

void expectOutputHas(const std::string& output, const std::vector<std::string>& needles) {
  for (const std::string& needle : needles)
    EXPECT_NE(output.find(needle), std::string::npos) << "no '" << needle << "' in:\n" << output;
}

void expectCleanOutcome(const std::function<void()>& action, const std::string& which) {
  try {
    action();
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << which << "\n" << e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << which << ": threw a " << typeid(e).name()
                  << ", not a pluvia::Error: " << e.what();
  }
}

CommandResult runPluviaTimed(const std::vector<std::string>& args) {
  const auto start = std::chrono::steady_clock::now();
  CommandResult result = runPluvia(args);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::string command;
  for (const auto& arg : args) command += (command.empty() ? "" : " ") + arg;
  std::cout << result.output << command << " took " << seconds << " s\n";
  return result;
}

CsvTable readCsvTable(const stdfs::path& path) {
  CsvTable table;
  std::ifstream file(path);
  if (!std::getline(file, table.header)) return table;
  const std::vector<std::string> names = splitCsv(table.header);
  for (size_t i = 0; i < names.size(); ++i) table.column[names[i]] = i;
  for (std::string line; std::getline(file, line);) {
    if (line.empty()) continue;
    std::vector<std::string> fields = splitCsv(line);
    if (fields.size() != names.size()) {
      ADD_FAILURE() << path << ": " << fields.size() << " fields, the header has " << names.size()
                    << ": " << line;
      continue;
    }
    table.lines.push_back(line);
    table.rows.push_back(std::move(fields));
  }
  return table;
}

bool hasColumns(const CsvTable& table, const std::vector<std::string>& names) {
  bool all = true;
  for (const std::string& name : names) {
    if (table.column.count(name)) continue;
    ADD_FAILURE() << "no column '" << name << "' in: " << table.header;
    all = false;
  }
  return all;
}

void expectPlot(const stdfs::path& path) {
  ASSERT_TRUE(stdfs::exists(path)) << path;
  const Image image = readImageFile(path);
  EXPECT_GT(image.width, 0) << path;
  EXPECT_GT(image.height, 0) << path;
}

void expectFiniteMeasures(const CsvTable& table, size_t row, const std::vector<std::string>& names,
                          bool nonNegative) {
  const std::string& line = table.lines[row];
  for (const std::string& name : names) {
    const double value = parseNumber(table.rows[row][table.column.at(name)], line);
    EXPECT_TRUE(std::isfinite(value)) << name << " in: " << line;
    if (nonNegative) {
      EXPECT_GE(value, 0.0) << name << " in: " << line;
    }
  }
}

QuickReport runQuickReport(const stdfs::path& dir, const std::string& name,
                           const std::vector<std::string>& extraArgs) {
  QuickReport report;
  report.csv = dir / (name + ".csv");
  report.plot = dir / (name + ".png");
  std::vector<std::string> args{
      "report", name, "--quick", "--csv", report.csv.string(), "--plot", report.plot.string()};
  args.insert(args.end(), extraArgs.begin(), extraArgs.end());
  report.result = runPluviaTimed(args);
  report.table = readCsvTable(report.csv);
  return report;
}

void expectReportRejectsMissing(const std::string& name, const std::string& flag,
                                const stdfs::path& missing) {
  const CommandResult r = runPluvia({"report", name, "--quick", flag, missing.string()});
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find(flag), std::string::npos) << r.output;
}

size_t residentBytes() {
  std::ifstream statm("/proc/self/statm");
  size_t pages = 0, resident = 0;
  statm >> pages >> resident;
  return resident * static_cast<size_t>(::sysconf(_SC_PAGESIZE));
}

std::string writePlateSequence(const stdfs::path& dir, int first, int last, int width, int height,
                               const std::function<void(Image&, int)>& paint) {
  for (int f = first; f <= last; ++f) {
    Image image(width, height);
    paint(image, f);
    char name[64];
    std::snprintf(name, sizeof name, "plate.%04d.png", f);
    writeImageFile(dir / name, image);
  }
  return (dir / "plate.####.png").string();
}

std::string writePixelPlate(const stdfs::path& dir, int first, int last, int width, int height,
                            const PixelPaint& paint) {
  return writePlateSequence(dir, first, last, width, height, [&](Image& image, int frame) {
    for (int y = 0; y < image.height; ++y)
      for (int x = 0; x < image.width; ++x) paint(image.pixel(x, y), x, y, frame);
  });
}

std::string writeTexturedPlate(const stdfs::path& dir, int first, int last, int width, int height) {
  return writePixelPlate(dir, first, last, width, height, [](float* p, int x, int y, int frame) {
    p[0] = float((x * 7 + y * 3 + frame) % 256) / 255.0f;
    p[1] = float((x * 2 + y * 5) % 256) / 255.0f;
    p[2] = float((x + y * 11) % 256) / 255.0f;
  });
}

EquirectMap equirectOf(
    int width, int height,
    const std::function<std::array<double, 3>(const std::array<double, 3>&)>& radiance) {
  EquirectMap map(width, height);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const std::array<double, 3> l = radiance(equirectTexelDirection(width, height, x, y));
      for (int c = 0; c < 3; ++c) map.texel(x, y)[c] = float(l[size_t(c)]);
    }
  }
  return map;
}

stdfs::path writeTextFile(const stdfs::path& dir, const std::string& name,
                          const std::string& text) {
  const stdfs::path path = dir / name;
  std::ofstream(path) << text;
  return path;
}

}  // namespace pluvia::test
