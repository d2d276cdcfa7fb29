#include "io/movie_probe.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include <fmt/format.h>

#include "io/metadata_names.h"
#include "util/error.h"
#include "util/subprocess.h"

namespace pluvia {
namespace {

// A timing whose average rate is off the nominal one by more than this is variable.
constexpr double kRateTolerance = 0.005;
// Above this a "nominal" rate is a timestamp resolution (90000/1), not a frame rate.
constexpr double kMaxNominalFps = 240.0;

// ffprobe's "flat" output: key=value lines, strings in double quotes with \" and \\ escaped.
std::map<std::string, std::string> parseFlat(const std::string& text) {
  std::map<std::string, std::string> values;
  for (size_t start = 0; start < text.size();) {
    size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    const std::string line = text.substr(start, end - start);
    start = end + 1;
    const size_t equals = line.find('=');
    if (equals == std::string::npos) continue;
    std::string value = line.substr(equals + 1);
    if (value.size() >= 2 && value.front() == '"' && value.back() == '"') {
      std::string unquoted;
      for (size_t i = 1; i + 1 < value.size(); ++i) {
        if (value[i] == '\\' && i + 2 < value.size()) ++i;
        unquoted += value[i];
      }
      value = unquoted;
    }
    values[line.substr(0, equals)] = value;
  }
  return values;
}

double parseRate(const std::string& text) {
  const size_t slash = text.find('/');
  const double numerator = std::atof(text.substr(0, slash).c_str());
  const double denominator = slash == std::string::npos ? 1.0 : std::atof(text.c_str() + slash + 1);
  return denominator > 0 ? numerator / denominator : 0.0;
}

int64_t parseCount(const std::string& text) {
  int64_t value = 0;
  std::from_chars(text.data(), text.data() + text.size(), value);
  return value;
}

// Bits per sample from the pixel format's name ("yuv420p10le" 10, "p016le" 16, "rgb48le" 16).
int bitsOfPixelFormat(const std::string& name) {
  if (name.find("48") != std::string::npos || name.find("64") != std::string::npos) return 16;
  size_t end = name.size();
  if (name.ends_with("le") || name.ends_with("be")) end -= 2;
  size_t begin = end;
  while (begin > 0 && std::isdigit(static_cast<unsigned char>(name[begin - 1]))) --begin;
  const int bits = begin < end ? std::atoi(name.substr(begin, end - begin).c_str()) : 8;
  return bits > 8 && bits <= 16 ? bits : 8;
}

}  // namespace

MovieProbe probeMovie(const std::string& path) {
  const ErrorContext context{"read", {}, path};
  if (!programAvailable("ffprobe") || !programAvailable("ffmpeg")) {
    throw Error("ffmpeg and ffprobe are needed to read the movie " + path + " but are not on PATH",
                context);
  }
  const ProcessResult result = runProcess(
      {"ffprobe", "-v", "error", "-select_streams", "v:0", "-show_entries",
       "stream=width,height,pix_fmt,bits_per_raw_sample,r_frame_rate,avg_frame_rate,nb_frames,"
       "duration,color_primaries,color_transfer,color_space,color_range:"
       "stream_tags:stream_side_data=rotation:format=duration:format_tags:"
       "packet=pts_time,duration_time",
       "-of", "flat", "file:" + path});
  const std::map<std::string, std::string> values = parseFlat(result.output);
  auto value = [&](const std::string& key) {
    auto found = values.find(key);
    return found == values.end() || found->second == "N/A" ? std::string() : found->second;
  };
  const std::string stream = "streams.stream.0.";
  if (result.exitCode == 0 && value(stream + "width").empty())
    throw Error(fmt::format("movie {} has no picture: no video stream (audio only, or none)", path),
                context);
  if (result.exitCode != 0) {
    // ffprobe's own words, without the fields it printed before it stopped.
    std::string reason;
    std::istringstream lines(result.output);
    for (std::string line; std::getline(lines, line);)
      if (!line.empty() && !values.count(line.substr(0, line.find('='))))
        reason += (reason.empty() ? "" : "; ") + line;
    throw Error(fmt::format("cannot open movie {} (not a movie FFmpeg can decode, or truncated){}",
                            path, reason.empty() ? "" : ": " + reason),
                context);
  }
  MovieProbe probe;
  probe.width = std::atoi(value(stream + "width").c_str());
  probe.height = std::atoi(value(stream + "height").c_str());
  for (const auto& [key, text] : values) {
    // ffmpeg turns the picture upright by default; a quarter turn swaps the size.
    const bool rotation = key.starts_with(stream + "side_data_list.") && key.ends_with(".rotation");
    if ((rotation || key == stream + "tags.rotate") &&
        std::abs(std::atoi(text.c_str())) % 180 == 90)
      std::swap(probe.width, probe.height);
  }
  probe.pixelFormat = value(stream + "pix_fmt");
  probe.bitsPerSample =
      std::max(bitsOfPixelFormat(probe.pixelFormat),
               std::min(16, std::atoi(value(stream + "bits_per_raw_sample").c_str())));
  // The coded frames, and where the last one ends.
  double codedEnd = 0;
  for (int64_t i = 0;; ++i) {
    const std::string packet = fmt::format("packets.packet.{}.", i);
    if (!values.count(packet + "pts_time")) break;
    ++probe.packets;
    codedEnd = std::max(codedEnd, std::atof(value(packet + "pts_time").c_str()) +
                                      std::atof(value(packet + "duration_time").c_str()));
  }
  const int64_t listed = parseCount(value(stream + "nb_frames"));
  std::string durationText = value(stream + "duration");
  if (durationText.empty()) durationText = value("format.duration");
  const double duration = std::atof(durationText.c_str());
  const double nominal = parseRate(value(stream + "r_frame_rate"));
  const double average = parseRate(value(stream + "avg_frame_rate"));
  // Variable: the average rate is not the nominal one, or the container lists more frames than
  // it codes while the coded ones still reach its end (an AVI index with empty "hold the last
  // frame" entries), and its duration spans the frames it lists; a container that lists none
  // (Matroska, whose average rate is its nominal one) the same with the frames its duration
  // holds at the nominal rate. Coded frames that stop early, or a header listing far more frames
  // than its duration holds (an AVI cut short, its index gone: 795 listed, 0.2 s), are a
  // truncated file, not a variable rate: the frame count check then refuses it.
  const double heldFrames = listed > 0 ? static_cast<double>(listed) : duration * nominal;
  const bool holdsFrames = probe.packets > 0 &&
                           static_cast<double>(probe.packets) + 0.5 < heldFrames && nominal > 0 &&
                           duration > 0 && codedEnd >= duration - 1.5 / nominal &&
                           std::abs(heldFrames - duration * nominal) <= 1.5;
  probe.variableRate =
      (nominal > 0 && average > 0 && std::abs(average - nominal) > kRateTolerance * nominal) ||
      holdsFrames;
  if (nominal > 0 && nominal <= kMaxNominalFps) {
    probe.rate = value(stream + "r_frame_rate");
    probe.fps = nominal;
  } else if (!probe.variableRate && average > 0 && average <= kMaxNominalFps) {
    probe.rate = value(stream + "avg_frame_rate");
    probe.fps = average;
  } else {
    throw Error(fmt::format("movie {} has a variable frame rate and no nominal rate to conform it "
                            "to (ffprobe: r_frame_rate {}, avg_frame_rate {}): conform it first, "
                            "e.g. ffmpeg -i IN -vf fps=24 OUT",
                            path, value(stream + "r_frame_rate"), value(stream + "avg_frame_rate")),
                context);
  }
  if (probe.variableRate && duration > 0) {
    probe.frames = std::llround(duration * probe.fps);
  } else if (listed > 0) {
    probe.frames = listed;
  } else if (duration > 0) {
    probe.frames = std::llround(duration * probe.fps);
  } else {
    probe.frames = probe.packets;
  }
  // Timecode: the stream's (a QuickTime tmcd track shows on the video stream) or the file's.
  std::string timecode = value(stream + "tags.timecode");
  if (timecode.empty()) timecode = value("format.tags.timecode");
  if (!timecode.empty()) probe.metadata["smpte:TimeCode"] = timecode;
  for (const char* tag : {"make", "model"}) {
    for (const std::string& key : {"format.tags." + std::string(tag),
                                   "format.tags.com.apple.quicktime." + std::string(tag)}) {
      if (!value(key).empty())
        probe.metadata[tag == std::string("make") ? "Make" : "Model"] = value(key);
    }
  }
  // The shutter, where the camera tagged it (names differ by maker: "shutter_angle",
  // "com.sony.shutter_speed" as "1/100", "...camera.shutterAngle"): as ExposureTime in
  // seconds or ShutterAngle in degrees, OpenImageIO's and the EXR attributes' names.
  for (const auto& [key, text] : values) {
    if (!key.starts_with("format.tags.") && !key.starts_with(stream + "tags.")) continue;
    const std::string name = key.substr(key.find_last_of('.') + 1);
    if (metadataNameEndsWith(name, "shutterangle")) probe.metadata["ShutterAngle"] = text;
    const double seconds = parseRate(text);  // "1/100" or "0.01"
    // A phone's lens (Apple's "com.apple.quicktime.camera.focal_length.35mm_equivalent"), as
    // EXIF's FocalLengthIn35mmFilm (pipeline/plate_lens.h).
    if (metadataNameEndsWith(key, "focallength.35mmequivalent"))
      probe.metadata["Exif:FocalLengthIn35mmFilm"] = text;
    if ((metadataNameEndsWith(name, "shutterspeed") ||
         metadataNameEndsWith(name, "exposuretime")) &&
        std::isfinite(seconds) && seconds > 0.0)
      probe.metadata["ExposureTime"] = fmt::format("{:g}", seconds);
  }

  for (const char* field : {"color_primaries", "color_transfer", "color_space", "color_range"}) {
    const std::string text = value(stream + field);
    if (!text.empty() && text != "unknown") probe.metadata[std::string("ffmpeg:") + field] = text;
  }
  return probe;
}

}  // namespace pluvia
