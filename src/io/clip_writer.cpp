#include "io/clip_writer.h"

#include <algorithm>
#include <filesystem>
#include <functional>

#include <fmt/format.h>

#include "io/image_file_writer.h"
#include "io/movie_writer.h"
#include "io/sequence_pattern.h"
#include "util/error.h"
#include "util/fs.h"

namespace pluvia {
namespace {

std::string joined(const std::vector<std::string>& items) {
  std::string text;
  for (const std::string& item : items) text += (text.empty() ? "" : ", ") + item;
  return text;
}

// JPEG, DPX (as written here) and Radiance HDR hold RGB only.
bool formatKeepsAlpha(const std::string& extension) {
  return extension != "jpg" && extension != "jpeg" && extension != "dpx" && extension != "hdr";
}

bool contains(const std::vector<std::string>& items, const std::string& item) {
  return std::find(items.begin(), items.end(), item) != items.end();
}

// Where a frame's files go: the beauty, and the AOV files of formats that cannot hold AOVs as
// extra channels ("out.####.png" -> "out.rain.0001.png"; depth always "out.depth.0001.exr").
struct FrameNaming {
  std::function<std::string(int64_t)> beauty;
  std::function<std::string(const std::string& aov, const std::string& suffix, int64_t)> aov;
};

std::string withExtension(const std::string& suffix, const std::string& extension) {
  const size_t dot = suffix.rfind('.');
  return (dot == std::string::npos ? suffix : suffix.substr(0, dot)) + "." + extension;
}

FrameNaming namingFor(const OutputTarget& output) {
  if (output.pattern) {
    return {
        [p = *output.pattern](int64_t frame) { return p.pathFor(frame); },
        [p = *output.pattern](const std::string& aov, const std::string& suffix, int64_t frame) {
          return SequencePattern{p.prefix + aov + ".", suffix, p.padding}.pathFor(frame);
        }};
  }
  // A movie or a single image: every frame goes to the same file (a still in, a still out).
  const std::filesystem::path path(output.path);
  const std::string stem = (path.parent_path() / path.stem()).string();
  return {[path = output.path](int64_t) { return path; },
          [stem](const std::string& aov, const std::string& suffix, int64_t) {
            return stem + "." + aov + suffix;
          }};
}

std::string suffixOf(const OutputTarget& output) {
  if (output.pattern) return output.pattern->suffix;
  return std::filesystem::path(output.path).extension().string();
}

// The AOV's own file (formats without extra channels): depth always, and every AOV of an HDR
// output, go to EXR (Radiance holds RGB only).
std::string aovPathFor(const FrameNaming& naming, const std::string& suffix,
                       const std::string& extension, const std::string& aov, int64_t frame) {
  const bool asExr = aov == kDepthPlane || extension == "hdr";
  return naming.aov(aov, asExr ? withExtension(suffix, "exr") : suffix, frame);
}

// The AOV's planes as channels: a single plane "matte" -> "matte.Y" ("depth" -> "depth.Z", in
// full float), or the four planes "rain.R".."rain.A" -> channels of the same names.
// The depth's sky, +inf in the render, goes out as kSkyDepthInAovMeters through `depthWritten`
// (which must outlive the channels).
std::vector<OutputChannel> aovChannels(const std::string& aov, const Image& image, int64_t frame,
                                       const std::string& path, std::vector<float>& depthWritten) {
  auto checkedPlane = [&](const std::string& name) {
    const std::vector<float>* plane = image.findPlane(name);
    if (plane && plane->size() != image.pixelCount()) {
      throw Error(fmt::format("plane '{}' of frame {} holds {} values for {}x{} pixels", name,
                              frame, plane->size(), image.width, image.height),
                  {"write", frame, path});
    }
    return plane;
  };
  if (const std::vector<float>* plane = checkedPlane(aov)) {
    if (aov != kDepthPlane) return {{aov + ".Y", plane->data(), 1}};
    depthWritten.resize(plane->size());
    for (size_t i = 0; i < plane->size(); ++i)
      depthWritten[i] = std::min((*plane)[i], kSkyDepthInAovMeters);
    return {{aov + ".Z", depthWritten.data(), 1, true}};
  }
  std::vector<OutputChannel> channels;
  for (const char* component : {"R", "G", "B", "A"}) {
    const std::vector<float>* plane = checkedPlane(aov + "." + component);
    if (!plane) {
      throw Error(
          fmt::format("AOV '{}' was asked for, but frame {} has no plane '{}' nor '{}.R'..'{}.A'",
                      aov, frame, aov, aov, aov),
          {"write", frame, path});
    }
    channels.push_back({aov + "." + component, plane->data(), 1});
  }
  return channels;
}

class ImageSequenceWriter final : public ClipWriter {
 public:
  ImageSequenceWriter(const OutputTarget& output, int width, int height, WriterOptions options)
      : naming_(namingFor(output)),
        suffix_(suffixOf(output)),
        extension_(lowerExtension(output.path)),
        width_(width),
        height_(height),
        options_(std::move(options)) {}

  void write(int64_t frame, const Image& image) override {
    const std::string path = naming_.beauty(frame);
    if (image.width != width_ || image.height != height_) {
      throw Error(fmt::format("frame {} is {}x{} but the output {} was opened for {}x{}", frame,
                              image.width, image.height, path, width_, height_),
                  {"write", frame, path});
    }
    // Every AOV plane is looked up before anything is written: a missing one leaves no files.
    std::vector<OutputChannel> channels = beautyChannels(image);
    std::vector<std::pair<std::string, std::vector<OutputChannel>>> aovFiles;
    std::vector<float> depthWritten;
    for (const std::string& aov : options_.aovs) {
      if (extension_ == "exr") {
        std::vector<OutputChannel> extra = aovChannels(aov, image, frame, path, depthWritten);
        channels.insert(channels.end(), extra.begin(), extra.end());
      } else {
        aovFiles.push_back(aovFile(aov, image, frame, depthWritten));
      }
    }
    ImageFileOptions fileOptions;
    fileOptions.exrFullFloat = options_.exrSampleType == "float";
    fileOptions.exrCompression = options_.exrCompression;
    fileOptions.tiffFloat = options_.tiffSampleType == "float";
    fileOptions.dataWindow = options_.dataWindow;
    fileOptions.displayWindow = options_.displayWindow;
    if (options_.timecode)
      fileOptions.timecode = options_.timecode->plus(frame - options_.firstFrame);
    // AOV files hold linear values whatever the beauty's space (linearAovTags); depth is data.
    const ColorTags aovTags = linearAovTags();
    for (const auto& [aovPath, aovSamples] : aovFiles) {
      const bool depth = aovSamples.size() == 1 && aovSamples.front().name == "Z";
      fileOptions.color = depth ? nullptr : &aovTags;
      writeImageFile(aovPath, width_, height_, aovSamples, options_.metadata, frame, fileOptions);
    }
    fileOptions.color = &options_.color;
    writeImageFile(path, width_, height_, channels, options_.metadata, frame, fileOptions);
  }

  void close() override {}
  bool isMovie() const override { return false; }
  std::string pathFor(int64_t frame) const override { return naming_.beauty(frame); }

 private:
  std::vector<OutputChannel> beautyChannels(const Image& image) const {
    std::vector<OutputChannel> channels;
    for (const char* name : {"R", "G", "B", "A"}) {
      if (channels.size() < 3 || (formatKeepsAlpha(extension_) && options_.alpha)) {
        channels.push_back({name, image.rgba.data() + channels.size(), 4});
      }
    }
    return channels;
  }

  // Formats without extra channels get one file per AOV, in the output's format, except where
  // that cannot hold it: depth is in metres and goes to EXR, and so do all AOVs of an HDR
  // output (Radiance holds RGB only). Formats without alpha drop an AOV's alpha as they drop
  // the beauty's.
  std::pair<std::string, std::vector<OutputChannel>> aovFile(
      const std::string& aov, const Image& image, int64_t frame,
      std::vector<float>& depthWritten) const {
    const bool asExr = aov == kDepthPlane || extension_ == "hdr";
    const std::string path = aovPathFor(naming_, suffix_, extension_, aov, frame);
    std::vector<OutputChannel> channels = aovChannels(aov, image, frame, path, depthWritten);
    // In a file of its own the AOV's channels drop its name: "rain.R" -> "R", "depth.Z" -> "Z".
    for (OutputChannel& channel : channels)
      channel.name = channel.name.substr(channel.name.rfind('.') + 1);
    if (!asExr && !formatKeepsAlpha(extension_) && channels.size() == 4) channels.pop_back();
    return {path, channels};
  }

  FrameNaming naming_;
  std::string suffix_;
  std::string extension_;
  int width_;
  int height_;
  WriterOptions options_;
};

// The AOV's channels as one RGBA image for a movie: R, G, B, A as they are, or a single plane
// as grey with alpha 1.
Image aovImage(const std::string& aov, const Image& image, int64_t frame, const std::string& path) {
  std::vector<float> unused;
  const std::vector<OutputChannel> channels = aovChannels(aov, image, frame, path, unused);
  Image out(image.width, image.height);
  for (size_t i = 0; i < image.pixelCount(); ++i) {
    for (int c = 0; c < 4; ++c) {
      const OutputChannel& from = channels[channels.size() == 4 ? c : 0];
      out.rgba[i * 4 + c] =
          channels.size() == 4 || c < 3 ? from.samples[i * from.strideFloats] : 1.0f;
    }
  }
  return out;
}

// A movie and one movie per AOV beside it ("out.mov" -> "out.rain.mov"), each with its alpha,
// so that the rain element alone reaches an editor or a comp as ProRes 4444 with its matte.
class MovieWithAovsWriter final : public ClipWriter {
 public:
  MovieWithAovsWriter(const OutputTarget& output, int width, int height,
                      const WriterOptions& options)
      : beauty_(openMovieWriter(output.path, width, height, options, false)) {
    const FrameNaming naming = namingFor(output);
    // AOV movies hold rain, mattes and light alone, linear whatever the beauty's space.
    WriterOptions aovOptions = options;
    aovOptions.color = linearAovTags();
    for (const std::string& aov : options.aovs) {
      aovs_.push_back({aov, openMovieWriter(naming.aov(aov, suffixOf(output), 0), width, height,
                                            aovOptions, true)});
    }
  }

  void write(int64_t frame, const Image& image) override {
    beauty_->write(frame, image);
    for (const auto& [aov, writer] : aovs_)
      writer->write(frame, aovImage(aov, image, frame, writer->pathFor(frame)));
  }

  // Every movie is finished even when one fails; the first failure is then thrown.
  void close() override {
    std::exception_ptr failure;
    for (ClipWriter* writer : writers()) {
      try {
        writer->close();
      } catch (...) {
        if (!failure) failure = std::current_exception();
      }
    }
    if (failure) std::rethrow_exception(failure);
  }

  bool isMovie() const override { return true; }
  std::string pathFor(int64_t frame) const override { return beauty_->pathFor(frame); }

 private:
  std::vector<ClipWriter*> writers() const {
    std::vector<ClipWriter*> all{beauty_.get()};
    for (const auto& [aov, writer] : aovs_) all.push_back(writer.get());
    return all;
  }

  std::unique_ptr<ClipWriter> beauty_;
  std::vector<std::pair<std::string, std::unique_ptr<ClipWriter>>> aovs_;
};

// The picture of a frame that holds overscan around it, its planes too.
Image croppedTo(const Image& image, const PixelWindow& window) {
  Image out(window.width, window.height);
  for (int y = 0; y < window.height; ++y) {
    const float* from = image.pixel(window.x, window.y + y);
    std::copy(from, from + size_t(window.width) * 4, out.pixel(0, y));
  }
  for (const auto& [name, plane] : image.planes) {
    std::vector<float>& to = out.plane(name);
    for (int y = 0; y < window.height; ++y) {
      const auto from = plane.begin() + ptrdiff_t((window.y + y) * image.width + window.x);
      std::copy(from, from + window.width, to.begin() + ptrdiff_t(y) * window.width);
    }
  }
  return out;
}

// Formats other than EXR hold the picture alone: a frame with overscan is cropped to its
// display window before it is written.
class PictureWriter final : public ClipWriter {
 public:
  PictureWriter(std::unique_ptr<ClipWriter> writer, PixelWindow picture)
      : writer_(std::move(writer)), picture_(picture) {}
  void write(int64_t frame, const Image& image) override {
    writer_->write(frame, croppedTo(image, picture_));
  }
  void close() override { writer_->close(); }
  bool isMovie() const override { return writer_->isMovie(); }
  std::string pathFor(int64_t frame) const override { return writer_->pathFor(frame); }

 private:
  std::unique_ptr<ClipWriter> writer_;
  PixelWindow picture_;
};

}  // namespace

std::unique_ptr<ClipWriter> openClipWriter(const OutputTarget& output, int width, int height,
                                           const WriterOptions& options) {
  const std::string extension = lowerExtension(output.path);
  const bool isSequenceFormat = contains(imageOutputExtensions(), extension);
  const bool isMovieFormat = contains(movieOutputExtensions(), extension);
  if (!isSequenceFormat && !isMovieFormat) {
    throw Error(
        fmt::format("unknown output format '{}' for {} (supported: image sequences {}; movies {})",
                    extension.empty() ? "(no extension)" : "." + extension, output.path,
                    joined(imageOutputExtensions()), joined(movieOutputExtensions())),
        {"write", {}, output.path});
  }
  if (width <= 0 || height <= 0) {
    throw Error(
        fmt::format("cannot write {}: frame size {}x{} is empty", output.path, width, height),
        {"write", {}, output.path});
  }
  if (options.exrSampleType != "half" && options.exrSampleType != "float") {
    throw Error(fmt::format("unknown EXR sample type '{}' for {} (known: half, float)",
                            options.exrSampleType, output.path),
                {"write", {}, output.path});
  }
  if (options.tiffSampleType != "uint16" && options.tiffSampleType != "float") {
    throw Error(fmt::format("unknown TIFF sample type '{}' for {} (known: uint16, float)",
                            options.tiffSampleType, output.path),
                {"write", {}, output.path});
  }
  if (isMovieFormat) checkMovieAovs(output.path, options);
  if (options.displayWindow && extension != "exr") {
    const PixelWindow picture = *options.displayWindow;
    if (!picture.fitsInside(width, height))
      throw Error(fmt::format("the picture {}x{} at ({}, {}) is not inside the {}x{} frame of {}",
                              picture.width, picture.height, picture.x, picture.y, width, height,
                              output.path),
                  {"write", {}, output.path});
    WriterOptions pictureOnly = options;
    pictureOnly.displayWindow.reset();
    pictureOnly.dataWindow.reset();
    return std::make_unique<PictureWriter>(
        openClipWriter(output, picture.width, picture.height, pictureOnly), picture);
  }
  const std::string firstPath = isMovieFormat ? output.path : namingFor(output).beauty(0);
  fs::ensureParentFolder(firstPath, options.makeFolders);
  if (isMovieFormat && !options.aovs.empty())
    return std::make_unique<MovieWithAovsWriter>(output, width, height, options);
  if (isMovieFormat) return openMovieWriter(output.path, width, height, options, false);
  return std::make_unique<ImageSequenceWriter>(output, width, height, options);
}

void checkMovieAovs(const std::string& output, const WriterOptions& options) {
  if (options.aovs.empty()) return;
  if (contains(options.aovs, kDepthPlane))
    throw Error(fmt::format("the depth AOV is in metres and cannot go into the movie {}: write "
                            "an EXR sequence such as out.####.exr",
                            output),
                {"write", {}, output});
  const std::vector<std::string> withAlpha = codecsWithAlpha();
  if (!contains(withAlpha, options.codec))
    throw Error(fmt::format("AOVs ({}) go into movies of their own beside {} only with their "
                            "alpha: --codec {}, or write an image sequence such as out.####.exr",
                            joined(options.aovs), output, joined(withAlpha)),
                {"write", {}, output});
}

std::vector<std::string> framePaths(const OutputTarget& output,
                                    const std::vector<std::string>& aovs, int64_t frame) {
  const FrameNaming naming = namingFor(output);
  std::vector<std::string> paths = {naming.beauty(frame)};
  const std::string extension = lowerExtension(output.path);
  if (extension == "exr") return paths;
  if (output.isMovie()) {
    for (const std::string& aov : aovs) paths.push_back(naming.aov(aov, suffixOf(output), 0));
    return paths;
  }
  for (const std::string& aov : aovs)
    paths.push_back(aovPathFor(naming, suffixOf(output), extension, aov, frame));
  return paths;
}

bool outputIsLinear(const std::string& output) {
  const std::string extension = lowerExtension(output);
  return extension == "exr" || extension == "hdr";
}

}  // namespace pluvia
