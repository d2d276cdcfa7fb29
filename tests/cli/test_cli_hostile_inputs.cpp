// Inputs built to hurt get a one-line error naming them, before any memory is taken
// (adversarial S13, S14, S17, S20, S24): a header claiming 100000x100000 pixels, a padding of
// 2e9 digits, a preset with a key given twice or bytes after a NUL; and odd but legal ones work:
// a 1x5000 frame, a 240-character frame name.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "test_support.h"

using namespace pluvia;
using namespace pluvia::test;
namespace stdfs = std::filesystem;

TEST(CliHostileInputs, AHeaderClaimingAHugeFrameIsRefusedBeforeDecoding) {
  const stdfs::path dir = freshTempDir("hostile_bomb");
  {  // 24 bytes of header, no pixels: a decoder would allocate 30 GB first.
    std::ofstream bomb(dir / "bomb.ppm", std::ios::binary);
    bomb << "P6\n100000 100000\n255\n" << std::string(16, '\0');
  }
  const auto r = runPluvia({"render", (dir / "bomb.ppm").string(), "-p", "moderate", "-o",
                            (dir / "o" / "r.png").string()});
  EXPECT_EQ(r.exitCode, 1) << r.output;
  EXPECT_NE(r.output.find("bomb.ppm claims 100000x100000 pixels"), std::string::npos) << r.output;
  EXPECT_FALSE(stdfs::exists(dir / "o" / "r.png"));
}

TEST(CliHostileInputs, ATallOneColumnFrameRenders) {
  const stdfs::path dir = freshTempDir("hostile_tall");
  writeImageFile(dir / "tall.png", flatImage(1, 5000, 0.3f, 0.4f, 0.5f));
  const auto r = runPluvia({"render", (dir / "tall.png").string(), "-p", "moderate", "-o",
                            (dir / "o" / "r.png").string(), "-q"});
  EXPECT_EQ(r.exitCode, 0) << r.output;
  EXPECT_EQ(readImageFile(dir / "o" / "r.png").height, 5000);
}

TEST(CliHostileInputs, AHugePaddingIsRefusedInAFewWords) {
  const stdfs::path dir = freshTempDir("hostile_padding");
  const std::string plate = writeTexturedPlate(dir, 1, 2);
  const auto out = runPluvia({"render", plate, "-p", "moderate", "-o",
                              (dir / "r.%0100000000d.png").string(), "--frames", "1"});
  EXPECT_NE(out.exitCode, 0);
  EXPECT_LT(out.output.size(), 2000u);
  EXPECT_NE(out.output.find("at most 19"), std::string::npos) << out.output;
  const auto in = runPluvia({"render", (dir / "p.%02000000000d.png").string(), "-p", "moderate",
                             "-o", (dir / "o.####.png").string()});
  EXPECT_NE(in.exitCode, 0);
  EXPECT_NE(in.output.find("at most 19"), std::string::npos) << in.output;
}

TEST(CliHostileInputs, APresetWithADuplicateKeyOrANulByteIsInvalid) {
  const stdfs::path dir = freshTempDir("hostile_json");
  const stdfs::path twice =
      writeTextFile(dir, "dup.json",
                    R"({"pluvia":1,"extends":"moderate","rain":{"rate_mm_h":8,"rate_mm_h":90}})");
  auto r = runPluvia({"validate", twice.string()});
  EXPECT_EQ(r.exitCode, 1) << r.output;
  EXPECT_NE(r.output.find("\"rate_mm_h\" is given twice"), std::string::npos) << r.output;
  // The same key in two objects is fine.
  const stdfs::path apart = writeTextFile(
      dir, "apart.json",
      R"({"pluvia":1,"extends":"moderate","rain":{"enabled":true},"fog":{"enabled":true}})");
  EXPECT_EQ(runPluvia({"validate", apart.string()}).exitCode, 0);
  const stdfs::path nul = writeTextFile(
      dir, "nul.json", std::string(R"({"pluvia":1,"extends":"moderate"})") + '\0' + "garbage");
  r = runPluvia({"validate", nul.string()});
  EXPECT_EQ(r.exitCode, 1) << r.output;
  EXPECT_NE(r.output.find("a NUL byte"), std::string::npos) << r.output;
}

TEST(CliHostileInputs, AFrameNameNearTheFileSystemLimitIsWritten) {
  const stdfs::path dir = freshTempDir("hostile_name");
  const std::string plate = writeTexturedPlate(dir, 1, 1);
  const std::string stem(231, 'n');  // "nnn...n.0001.png": 240 bytes, legal
  const auto r = runPluvia(
      {"render", plate, "-p", "moderate", "-o", (dir / "o" / (stem + ".####.png")).string(), "-q"});
  EXPECT_EQ(r.exitCode, 0) << r.output;
  EXPECT_TRUE(stdfs::exists(dir / "o" / (stem + ".0001.png")));
  // A movie's too (adversarial S20): its temporary and ffmpeg's log beside it are cut to fit.
  const std::string movie = std::string(251, 'm') + ".mp4";  // 255 bytes
  const auto m = runPluvia({"render", plate, "-p", "moderate", "-o", (dir / "o" / movie).string()});
  EXPECT_EQ(m.exitCode, 0) << m.output;
  EXPECT_TRUE(stdfs::exists(dir / "o" / movie));
  // Over the limit: refused before any work, naming it.
  const auto over = runPluvia({"render", plate, "-p", "moderate", "-o",
                               (dir / "o2" / (std::string(250, 'n') + ".####.png")).string()});
  EXPECT_EQ(over.exitCode, 2) << over.output;
  EXPECT_NE(over.output.find("over the file system's 255"), std::string::npos) << over.output;
}

TEST(CliHostileInputs, AnOcioLutThatIsADeviceIsRefusedBeforeReading) {
  // Adversarial S26: a config whose output space's FileTransform reads a link to /dev/zero (or
  // a folder) would read until memory ran out; it is refused by name at once.
  const stdfs::path dir = freshTempDir("hostile_lut");
  const std::string plate = writeTexturedPlate(dir, 1, 2);
  stdfs::create_symlink("/dev/zero", dir / "lut.cube");
  stdfs::create_directory(dir / "folder.cube");
  for (const std::string lut : {"lut.cube", "folder.cube"}) {
    const stdfs::path config =
        writeTextFile(dir, "z.ocio",
                      "ocio_profile_version: 2\nsearch_path: .\nroles:\n  default: lin\n"
                      "  scene_linear: lin\nfile_rules:\n  - !<Rule> {name: Default, colorspace: "
                      "lin}\ncolorspaces:\n  - !<ColorSpace>\n    name: lin\n  - !<ColorSpace>\n"
                      "    name: zero\n    from_scene_reference: !<FileTransform> {src: " +
                          lut + ", interpolation: linear}\n");
    const auto r = runPluvia(
        {"render", plate, "-p", "moderate", "-o", (dir / "o" / "r.####.exr").string(), "--frames",
         "1", "--ocio", config.string(), "--in-colorspace", "lin", "--out-colorspace", "zero"});
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find("the LUT '" + lut + "'"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("is not a regular file"), std::string::npos) << r.output;
    EXPECT_FALSE(stdfs::exists(dir / "o" / "r.0001.exr"));
  }
}
