#pragma once
// Paths and small helpers shared by the tests.
#include <array>
#include <filesystem>
#include <functional>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "image/equirect.h"
#include "image/image.h"
#include "util/error.h"

namespace pluvia::test {

std::filesystem::path sourceDir();     // the repository root
std::filesystem::path pluviaBinary();  // build/pluvia
std::filesystem::path exampleClip();   // examples/street/street_plate.mp4
// ../shared/data beside the checkout (or $PLUVIA_SHARED_DATA); empty when absent, in which
// case tests that need it call GTEST_SKIP().
std::filesystem::path sharedData();
// A fresh, empty folder under the system temp dir, unique to this test; removed with the
// process's other folders when all its tests pass.
std::filesystem::path freshTempDir(const std::string& name);
// This process's resident memory, from /proc/self/statm.
size_t residentBytes();

struct CommandResult {
  int exitCode = -1;
  std::string output;  // stdout + stderr
};
// Runs build/pluvia with the arguments (no shell).
CommandResult runPluvia(const std::vector<std::string>& args);

// Starts build/pluvia with the arguments in the background, its stdout and stderr going to
// `log`; returns its pid.
int startPluvia(const std::vector<std::string>& args, const std::filesystem::path& log);
// Waits for a child; its exit code, or 1000 + the signal that killed it.
int waitForExit(int pid);
// Polls `ready` every 100 ms for up to `seconds`; whether it came to hold.
bool waitUntil(const std::function<bool()>& ready, double seconds = 60);

// A CSV line's fields; a double-quoted field may hold commas (the optics and lights reports'
// setting column), its quotes dropped.
std::vector<std::string> splitCsv(const std::string& line);
// A CSV field as a number; a field that is not wholly a number fails the test, naming `line`.
double parseNumber(const std::string& text, const std::string& line);

// How many lines of `text` start with one of `firstWords` (a report's table rows).
int countLinesStartingWith(const std::string& text, const std::set<std::string>& firstWords);

// Expects each of `needles` in `output` (a command's output, an error's message), printing it
// when one is missing.
void expectOutputHas(const std::string& output, const std::vector<std::string>& needles);

// Runs build/pluvia with the arguments like runPluvia, and prints its output and how long it took
// (a report test's log).
CommandResult runPluviaTimed(const std::vector<std::string>& args);

// A CSV file read whole (a report's table): the header's columns by name and the non-empty rows,
// split. A missing file leaves it empty; a row with another number of fields than the header
// fails the test and is left out.
struct CsvTable {
  std::string header;
  std::map<std::string, size_t> column;
  std::vector<std::string> lines;  // each row as written, for messages
  std::vector<std::vector<std::string>> rows;
};
CsvTable readCsvTable(const std::filesystem::path& path);
// Whether the table has every column named; each missing one fails the test, naming the header.
bool hasColumns(const CsvTable& table, const std::vector<std::string>& names);
// Expects the plot a report wrote at `path`: a file that decodes to a non-empty image.
void expectPlot(const std::filesystem::path& path);
// Expects each of `names` in row `row` of the table to be a finite number, and not negative
// where `nonNegative`; a failure names the measure and the row.
void expectFiniteMeasures(const CsvTable& table, size_t row, const std::vector<std::string>& names,
                          bool nonNegative);

// `pluvia report NAME --quick --csv DIR/NAME.csv --plot DIR/NAME.png` and `extraArgs`, timed
// (runPluviaTimed), with its table read back (empty when the command wrote none).
struct QuickReport {
  std::filesystem::path csv, plot;
  CommandResult result;
  CsvTable table;
};
QuickReport runQuickReport(const std::filesystem::path& dir, const std::string& name,
                           const std::vector<std::string>& extraArgs = {});
// `pluvia report NAME --quick FLAG MISSING` with a path that does not exist: a usage error
// (exit 2) whose message names FLAG.
void expectReportRejectsMissing(const std::string& name, const std::string& flag,
                                const std::filesystem::path& missing);

// A width x height equirectangular map whose texel centres hold radiance(direction) (RGB).
EquirectMap equirectOf(
    int width, int height,
    const std::function<std::array<double, 3>(const std::array<double, 3>&)>& radiance);

// Writes `text` to dir/name and returns the path.
std::filesystem::path writeTextFile(const std::filesystem::path& dir, const std::string& name,
                                    const std::string& text);

// A width x height image of one colour (alpha as Image makes it).
Image flatImage(int width, int height, float r, float g, float b);

// Reads an image file with OpenImageIO as float RGBA (no colour conversion).
Image readImageFile(const std::filesystem::path& path);
// Every channel of an image file (an EXR's AOVs too), interleaved as stored; a failure is
// reported to gtest and gives no channels.
struct ExrPixels {
  std::vector<std::string> channels;
  std::vector<float> samples;
};
ExrPixels readAllChannels(const std::filesystem::path& path);
// Sum of one channel's samples; -1 when the file has no such channel.
double channelSum(const ExrPixels& pixels, const std::string& name);
// Writes float RGBA (alpha dropped when `channels` is 3) to any format OpenImageIO knows.
void writeImageFile(const std::filesystem::path& path, const Image& image, int channels = 3);

// Writes frames first..last of a width x height plate as dir/plate.%04d.png, each painted by
// `paint(image, frame)`, and returns the pattern "dir/plate.####.png".
std::string writePlateSequence(const std::filesystem::path& dir, int first, int last, int width,
                               int height, const std::function<void(Image&, int)>& paint);

// writePlateSequence painted pixel by pixel: `paint(rgba, x, y, frame)` sets pixel (x, y)'s
// samples (alpha starts at 1).
using PixelPaint = std::function<void(float* rgba, int x, int y, int frame)>;
std::string writePixelPlate(const std::filesystem::path& dir, int first, int last, int width,
                            int height, const PixelPaint& paint);

// A writePixelPlate of diagonal ramps that move with the frame number, so a frame mix-up or a
// shifted frame shows.
std::string writeTexturedPlate(const std::filesystem::path& dir, int first, int last,
                               int width = 64, int height = 48);

// Runs a fuzz case: it may succeed or throw a pluvia::Error with a one-line message; a message of
// several lines or another exception fails the test, naming the case (`which`).
void expectCleanOutcome(const std::function<void()>& action, const std::string& which);

// Runs `action`, expecting a pluvia::Error whose message names `needle`; returns the error.
template <typename Action>
Error expectError(Action action, const std::string& needle) {
  try {
    action();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << "message: " << e.what();
    return e;
  }
  ADD_FAILURE() << "no pluvia::Error thrown (expected one naming " << needle << ")";
  return Error("none");
}

}  // namespace pluvia::test
