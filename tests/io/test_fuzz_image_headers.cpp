// Fuzzing the image readers in-process (issue 16): truncated and bit-flipped files of every input
// format (PNG, JPEG, EXR, TIFF, DPX). Each read either succeeds or throws pluvia::Error with a
// one-line message: never a crash, never another exception type.
#include <gtest/gtest.h>

#include <fstream>

#include "fuzz_mutations.h"
#include "io/image_file_reader.h"
#include "test_support.h"
#include "util/fs.h"

using namespace pluvia;
namespace stdfs = std::filesystem;

namespace {

constexpr uint32_t kSeed = 16;
constexpr int kCasesPerFormat = 300;
// Flips land in the first bytes, where the headers (and EXR's offset table) are.
constexpr size_t kHeaderBytes = 1024;

Image gradient(int w, int h) {
  Image image(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float* p = image.pixel(x, y);
      p[0] = float(x) / float(w);
      p[1] = float(y) / float(h);
      p[2] = float((x * y) % 7) / 7.0f;
    }
  return image;
}

}  // namespace

TEST(FuzzImageHeaders, TruncatedAndBitFlippedFilesOfEveryFormat) {
  const stdfs::path dir = test::freshTempDir("fuzz_images");
  test::Mutator mutator(kSeed);
  for (const std::string extension : {"png", "jpg", "exr", "tif", "dpx"}) {
    const stdfs::path original = dir / ("original." + extension);
    test::writeImageFile(original, gradient(64, 48));
    const std::string bytes = fs::readTextFile(original);
    const stdfs::path file = dir / ("case." + extension);
    for (int i = 0; i < kCasesPerFormat; ++i) {
      const std::string mutated = mutator.mutateBytes(bytes, kHeaderBytes);
      std::ofstream(file, std::ios::binary | std::ios::trunc) << mutated;
      const std::string which = extension + " case " + std::to_string(i);
      test::expectCleanOutcome(
          [&] {
            readImageHeader(file.string(), std::nullopt);
            readImageFile(file.string(), std::nullopt);
          },
          which);
      if (HasFailure()) {
        std::ofstream(dir / ("failed." + extension), std::ios::binary) << mutated;
        return;  // the failing file is kept beside the original
      }
    }
  }
}
