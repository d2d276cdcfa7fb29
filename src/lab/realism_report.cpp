#include "lab/realism_report.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <sstream>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

#include "derain/clean_plate.h"
#include "derain/motion_blur.h"
#include "image/contact_sheet.h"
#include "image/luminance.h"
#include "image/srgb.h"
#include "io/clip_reader.h"
#include "io/image_file_writer.h"
#include "lab/real_rain_clip.h"
#include "lab/report_numbers.h"
#include "util/error.h"
#include "util/log.h"
#include "util/timer.h"

namespace pluvia::lab {

using namespace derain;

namespace {

constexpr int kQuickWidthPx = 320, kQuickFrames = 8;
// The contact sheet's crops, at the report's width: where the real rain shows most.
constexpr int kCropWidthPx = 240, kCropHeightPx = 180;
// The rain layers on the sheet are shown times this over mid grey.
constexpr float kLayerGain = 3.0f;

// The crop of the frame where the real layer holds the most streak pixels.
cv::Rect busiestCrop(const cv::Mat1f& layer, const cv::Mat1b& valid, cv::Size crop) {
  crop.width = std::min(crop.width, layer.cols);
  crop.height = std::min(crop.height, layer.rows);
  const cv::Mat1b streaks = detectStreaks(layer, valid).mask;
  cv::Mat1d integral;
  cv::integral(streaks / 255, integral, CV_64F);
  cv::Rect best(0, 0, crop.width, crop.height);
  double bestCount = -1.0;
  for (int y = 0; y + crop.height <= layer.rows; y += crop.height / 4)
    for (int x = 0; x + crop.width <= layer.cols; x += crop.width / 4) {
      const double count = integral(y + crop.height, x + crop.width) - integral(y, x + crop.width) -
                           integral(y + crop.height, x) + integral(y, x);
      if (count > bestCount) bestCount = count, best = cv::Rect(x, y, crop.width, crop.height);
    }
  return best;
}

Image tileOf(const cv::Mat3f& codes) {
  Image tile(codes.cols, codes.rows);
  for (int y = 0; y < codes.rows; ++y)
    for (int x = 0; x < codes.cols; ++x)
      for (int c = 0; c < 3; ++c)
        tile.rgba[(size_t(y) * codes.cols + x) * 4 + c] =
            std::clamp(codes(y, x)[c] / 255.0f, 0.0f, 1.0f);
  return tile;
}

// A layer (codes) as grey around mid grey, times kLayerGain.
Image layerTile(const cv::Mat1f& layer) {
  cv::Mat3f grey;
  cv::Mat1f shown = layer * kLayerGain + 128.0f;
  cv::merge(std::vector<cv::Mat>{shown, shown, shown}, grey);
  return tileOf(grey);
}

struct SheetColumn {
  std::string label;
  std::vector<cv::Mat3f> frames;
  std::vector<cv::Mat1f> layers;
};

// Two rows per sheet: the middle frame's busiest crop as filmed or rendered, then its layer.
void writeContactSheet(const std::string& path, const std::vector<SheetColumn>& columns,
                       const cv::Rect& crop, size_t frame) {
  ContactSheet sheet(crop.size(), int(columns.size()), 2);
  for (size_t c = 0; c < columns.size(); ++c) {
    sheet.place(0, int(c), tileOf(columns[c].frames[frame](crop)), columns[c].label);
    sheet.place(1, int(c), layerTile(columns[c].layers[frame](crop)),
                fmt::format("{} layer x{:g}", columns[c].label, kLayerGain));
  }
  const Image& image = sheet.image();
  std::vector<OutputChannel> channels;
  for (int c = 0; c < 3; ++c)
    channels.push_back({std::string(1, "RGB"[c]), image.rgba.data() + c, 4});
  std::filesystem::create_directories(std::filesystem::path(path).parent_path());
  writeImageFile(path, image.width, image.height, channels, {}, std::nullopt);
}

struct ClipShutter {
  double seconds = 0.0;
  std::string source;
};

// The clip's shutter as a render of it finds it (stages/plate_shutter.h): its motion blur on the
// middle 7 frames (the display codes taken as sRGB), or, where that is a bound or nothing, the
// streaks of its rain (`rain`: the real layer's) when shorter, or the 180-degree shutter.
ClipShutter clipShutter(const RealClip& clip, const StreakStats& rain) {
  std::vector<cv::Mat1f> greys;
  for (const cv::Mat3f& rgb : clip.frames) {
    cv::Mat1f grey(rgb.size());
    for (int y = 0; y < rgb.rows; ++y)
      for (int x = 0; x < rgb.cols; ++x) {
        const cv::Vec3f& p = rgb(y, x);
        const std::array<double, 3> linear{srgbDecode(p[0] / 255.0), srgbDecode(p[1] / 255.0),
                                           srgbDecode(p[2] / 255.0)};
        grey(y, x) = float(rec709Luminance(linear));
      }
    greys.push_back(grey);
  }
  const size_t count = std::min<size_t>(greys.size(), 7), first = (greys.size() - count) / 2;
  const derain::ShutterFromBlur blur = derain::measureShutterFromBlur(
      {greys.begin() + ptrdiff_t(first), greys.begin() + ptrdiff_t(first + count)});
  ClipShutter shutter{0.5 / clip.fps,
                      "the 180-degree shutter (its motion blur: " + blur.summary + ")"};
  if (blur.measured) {
    shutter = {blur.shutterFraction / clip.fps,
               fmt::format("{}from its motion blur ({})", blur.upperBound ? "at most, " : "",
                           blur.summary)};
    if (!blur.upperBound) return shutter;
  }
  const double streaks = derain::shutterFromStreaksSeconds(rain.elongationByLightP50);
  if (streaks > 0.0 && streaks < shutter.seconds)
    shutter = {streaks,
               fmt::format("from its rain's streaks (by their light {:.1f} times as long "
                           "as wide, the median {:.1f} x {:.2f} px), shorter than 1/{:.0f} "
                           "s {}",
                           rain.elongationByLightP50, rain.lengthP50Px, rain.widthP50Px,
                           1.0 / shutter.seconds, shutter.source)};
  return shutter;
}

using Ratios = std::vector<std::pair<std::string, double>>;

// How far a ratio to real is off, either way: max(r, 1/r).
double factorOff(double ratio) {
  return std::max(ratio, 1.0 / ratio);
}

std::vector<double> ratioValues(const Ratios& ratios) {
  std::vector<double> values;
  for (const auto& [name, ratio] : ratios) values.push_back(ratio);
  return values;
}

// The largest max(r, 1/r), and the statistic's name in `name` when given.
double worstOf(const Ratios& ratios, std::string* name) {
  double worst = 0.0;
  for (const auto& [statistic, ratio] : ratios)
    if (const double off = factorOff(ratio); off > worst) {
      worst = off;
      if (name) *name = statistic;
    }
  return worst;
}

// A ratio to real; NaN where real has none.
double ratioTo(double value, double real) {
  return real > 0.0 ? value / real : std::nan("");
}

Ratios groundRatiosToReal(const GroundStats& row, const GroundStats& real) {
  return {{"blobs/Mpx", ratioTo(row.blobsPerMpx, real.blobsPerMpx)},
          {"area p50", ratioTo(row.areaP50Px, real.areaP50Px)},
          {"life", ratioTo(row.lifetimeFrames, real.lifetimeFrames)},
          {"dI p90", ratioTo(row.deltaP90, real.deltaP90)}};
}

// The ground's crop: the bottom rows of the frame, centred.
cv::Rect groundCrop(cv::Size frame, cv::Size crop) {
  crop.width = std::min(crop.width, frame.width);
  crop.height = std::min(crop.height, frame.height - int(kGroundTopFraction * frame.height));
  return {(frame.width - crop.width) / 2, frame.height - crop.height, crop.width, crop.height};
}

double dropContrastOf(const RealismRow& row) {
  return impliedDropContrastCodes(row.stats.energyPerSquareLengthP50, row.shutterSeconds);
}

}  // namespace

RealismReport runRealismReport(const RealismReportSettings& settings,
                               const RenderOnPlates& render) {
  RealismReport report;
  report.widthPx = settings.quick ? kQuickWidthPx : kReportWidthPx;
  const int frameCount = settings.quick ? kQuickFrames : settings.frames;
  std::vector<std::string> clips = settings.clips;
  if (clips.empty()) {
    const std::string nturain = defaultClip(settings.sharedData);
    if (nturain.empty()) {
      report.notes.push_back(
          "no real rain clip: NTURain ra1 is not in the shared data (give a clip, or --data)");
      return report;
    }
    clips.push_back(nturain);
  }
  for (const std::string& path : clips) {
    const auto started = std::chrono::steady_clock::now();
    const RealClip clip = readRealClip(path, frameCount, report.widthPx);
    const std::vector<CleanPlate> plates = cleanPlatesRgb(clip.frames);
    std::vector<SheetColumn> columns{{"real", clip.frames, {}}};
    RealismRow real;
    real.clip = clip.name;
    real.preset = "real";
    real.stats = measureLayers(clip.frames, plates, &columns[0].layers);
    real.typical = real.worst = real.groundWorst = 1.0;
    real.ground = measureGroundLayers(columns[0].layers);
    real.seconds = secondsSince(started);
    const ClipShutter shutter = clipShutter(clip, real.stats);
    real.shutterSeconds = shutter.seconds;
    report.rows.push_back(real);
    report.notes.push_back(fmt::format("{}: its shutter 1/{:.0f} s at {:g} fps, {}", clip.name,
                                       1.0 / shutter.seconds, clip.fps, shutter.source));
    std::vector<cv::Mat3f> plateImages;
    for (const CleanPlate& plate : plates) plateImages.push_back(plate.plate);
    const RealismRow* nearest = nullptr;
    for (const std::string& preset : settings.presets) {
      const auto renderStarted = std::chrono::steady_clock::now();
      SheetColumn column{
          preset, render(plateImages, clip.fps, clip.filmedWidthPx, shutter.seconds, preset), {}};
      RealismRow row;
      row.clip = clip.name;
      row.preset = preset;
      // Measured as the real rain is: against plates estimated from the frames themselves.
      row.stats = measureLayers(column.frames, cleanPlatesRgb(column.frames), &column.layers);
      row.ratios = ratiosToReal(row.stats, real.stats);
      row.typical = typicalFactor(ratioValues(row.ratios));
      row.worst = worstOf(row.ratios, &row.worstName);
      std::vector<cv::Mat1f> exactLayers;
      row.exactStats = measureLayers(column.frames, plates, &exactLayers);
      row.groundExact = measureGroundLayers(exactLayers);
      row.exactRatios = ratiosToReal(row.exactStats, real.stats);
      row.exactTypical = typicalFactor(ratioValues(row.exactRatios));
      row.exactWorst = worstOf(row.exactRatios, nullptr);
      row.ground = measureGroundLayers(column.layers);
      row.groundRatios = groundRatiosToReal(row.ground, real.ground);
      row.groundWorst = worstOf(row.groundRatios, nullptr);
      row.shutterSeconds = shutter.seconds;
      row.seconds = secondsSince(renderStarted);
      report.rows.push_back(row);
      columns.push_back(std::move(column));
    }
    if (!(real.stats.streaksPerMpx > 0.0)) {
      // No statistic has a real value to be a ratio of: "nearest x0.00" would be a number that
      // says nothing.
      report.notes.push_back(fmt::format(
          "{}: no rain streaks found in its {} frames measured (dI > 10 codes with a ridge, "
          "against its clean plates): nothing to compare the presets with (measure more frames: "
          "--frames)",
          clip.name, clip.frames.size()));
    } else {
      for (const RealismRow& row : report.rows)
        if (row.clip == clip.name && row.preset != "real" &&
            (!nearest || row.worst < nearest->worst))
          nearest = &row;
    }
    if (nearest) {
      int within = 0;
      for (const auto& [name, ratio] : nearest->ratios) within += factorOff(ratio) <= kRealismBound;
      report.notes.push_back(fmt::format(
          "{}: nearest preset {} (worst x{:.2f}, its {}; {} of {} statistics within x{:.2f}; "
          "typical x{:.2f})",
          clip.name, nearest->preset, nearest->worst, nearest->worstName, within,
          nearest->ratios.size(), kRealismBound, nearest->typical));
    }
    if (!settings.imagesDir.empty()) {
      const size_t middle = clip.frames.size() / 2;
      const cv::Rect crop = busiestCrop(columns[0].layers[middle], plates[middle].valid,
                                        cv::Size(kCropWidthPx * report.widthPx / kReportWidthPx,
                                                 kCropHeightPx * report.widthPx / kReportWidthPx));
      const std::string sheet = (std::filesystem::path(settings.imagesDir) /
                                 (std::filesystem::path(clip.name).stem().string() + "_sheet.png"))
                                    .string();
      writeContactSheet(sheet, columns, crop, middle);
      report.notes.push_back("contact sheet: " + sheet);
      const std::string ground =
          (std::filesystem::path(settings.imagesDir) /
           (std::filesystem::path(clip.name).stem().string() + "_ground_sheet.png"))
              .string();
      writeContactSheet(ground, columns, groundCrop(clip.frames[middle].size(), crop.size()),
                        middle);
      report.notes.push_back("ground contact sheet: " + ground);
    }
  }
  return report;
}

namespace {

struct Column {
  const char* header;
  int width;
  std::function<std::string(const RealismRow&)> value;
};

std::vector<Column> statColumns() {
  auto number = [](double StreakStats::*member, int decimals) {
    return
        [member, decimals](const RealismRow& r) { return fixedOrDash(r.stats.*member, decimals); };
  };
  return {
      {"clip", 14, [](const RealismRow& r) { return r.clip.substr(0, 13); }},
      {"preset", 10, [](const RealismRow& r) { return r.preset; }},
      {"typical", 8,
       [](const RealismRow& r) { return r.preset == "real" ? "-" : fixedOrDash(r.typical, 2); }},
      {"worst", 7,
       [](const RealismRow& r) { return r.preset == "real" ? "-" : fixedOrDash(r.worst, 2); }},
      {"cover%", 7, [](const RealismRow& r) { return percentOrDash(r.stats.coverage); }},
      {"dI p50", 7, number(&StreakStats::deltaP50, 1)},
      {"p90", 6, number(&StreakStats::deltaP90, 1)},
      {"p99", 6, number(&StreakStats::deltaP99, 1)},
      {"/Mpx", 7, number(&StreakStats::streaksPerMpx, 0)},
      {"len p50", 8, number(&StreakStats::lengthP50Px, 1)},
      {"wid p50", 8, number(&StreakStats::widthP50Px, 2)},
      {"peak p90", 9, number(&StreakStats::peakP90, 1)},
      {"L/W lit", 8, number(&StreakStats::elongationByLightP50, 2)},
      {"E p50", 7, number(&StreakStats::energyP50CodesPx, 0)},
      {"drop C", 7, [](const RealismRow& r) { return fixedOrDash(dropContrastOf(r), 1); }},
      {"angle", 7, number(&StreakStats::angleDeg, 1)},
      {"spread", 7, number(&StreakStats::angleSpreadDeg, 1)},
      {"dI dark", 8, number(&StreakStats::deltaDarkThird, 1)},
      {"dI brt", 7, number(&StreakStats::deltaBrightThird, 1)},
      {"corr", 6, number(&StreakStats::temporalCorrelation, 3)},
      {"time s", 7, [](const RealismRow& r) { return fixedOrDash(r.seconds, 1); }},
  };
}

// A ratio's column: its name and a space before it, at least 14 wide.
int ratioWidth(const std::string& name) {
  return std::max(14, int(name.size()) + 1);
}

}  // namespace

std::string formatRealismReport(const RealismReport& report) {
  std::ostringstream out;
  out << fmt::format(
      "Visible rain streaks (dI > 10 codes with a ridge, at {} px wide; false alarms from the "
      "negated layer subtracted), real footage against each preset on its clean plates (every "
      "layer against plates estimated from its own frames):\n",
      report.widthPx);
  const std::vector<Column> columns = statColumns();
  for (const Column& c : columns) out << fmt::format("{:>{}}", c.header, c.width);
  out << "\n";
  for (const RealismRow& row : report.rows) {
    for (const Column& c : columns) out << fmt::format("{:>{}}", c.value(row), c.width);
    out << "\n";
  }
  bool header = false;
  for (const RealismRow& row : report.rows) {
    if (row.ratios.empty()) continue;
    if (!header) {
      out << fmt::format(
          "\nRatios to real (! outside x{:.2f}; worst = the largest max(r, 1/r); typical = "
          "exp(mean |ln ratio|) over these):\n",
          kRealismBound);
      out << fmt::format("{:>14}{:>10}", "clip", "preset");
      for (const auto& [name, ratio] : row.ratios)
        out << fmt::format("{:>{}}", name, ratioWidth(name));
      out << fmt::format("{:>9}{:>9}{:>9}{:>9}\n", "worst", "typical", "exact wo", "exact ty");
      header = true;
    }
    out << fmt::format("{:>14}{:>10}", row.clip.substr(0, 13), row.preset);
    for (const auto& [name, ratio] : row.ratios)
      out << fmt::format("{:>{}}",
                         fixedOrDash(ratio, 2) + (factorOff(ratio) > kRealismBound ? "!" : " "),
                         ratioWidth(name));
    out << fmt::format("{:>9}{:>9}{:>9}{:>9}\n", fixedOrDash(row.worst, 2),
                       fixedOrDash(row.typical, 2), fixedOrDash(row.exactWorst, 2),
                       fixedOrDash(row.exactTypical, 2));
  }
  if (header)
    out << "(exact: the rendered layer against the exact plates it was rendered on; the real "
           "layer can only be taken against estimated ones, so the columns before it compare like "
           "with like. drop C: each streak's sum of dI over its length squared, inverted at the "
           "clip's shutter into its drop's contrast over the background, median, codes)\n";
  out << fmt::format(
      "\nGround (the frame's bottom third: blobs of |dI| > {:g} codes, 2-400 px, at most x{:g} "
      "longer than wide: splashes and ripples, not streaks; ratios to real, ! outside x{:.2f}):\n",
      kGroundBlobCodes, kRoundAspect, kGroundBound);
  out << fmt::format("{:>14}{:>10}{:>10}{:>9}{:>8}{:>8}{:>11}{:>10}{:>8}{:>8}{:>8}{:>12}\n", "clip",
                     "preset", "blobs/Mpx", "area p50", "life fr", "dI p90", "r blobs", "r area",
                     "r life", "r dI", "worst", "exact /Mpx");
  for (const RealismRow& row : report.rows) {
    const GroundStats& g = row.ground;
    out << fmt::format("{:>14}{:>10}{:>10}{:>9}{:>8}{:>8}", row.clip.substr(0, 13), row.preset,
                       fixedOrDash(g.blobsPerMpx, 0), fixedOrDash(g.areaP50Px, 1),
                       fixedOrDash(g.lifetimeFrames, 2), fixedOrDash(g.deltaP90, 1));
    const std::array<int, 4> widths{11, 10, 8, 8};
    for (size_t i = 0; i < widths.size(); ++i) {
      const double ratio = i < row.groundRatios.size() ? row.groundRatios[i].second : std::nan("");
      const bool off = std::isfinite(ratio) && factorOff(ratio) > kGroundBound;
      out << fmt::format("{:>{}}",
                         row.preset == "real" ? "-" : fixedOrDash(ratio, 2) + (off ? "!" : " "),
                         widths[i]);
    }
    out << fmt::format("{:>8}{:>12}\n",
                       row.preset == "real" ? "-" : fixedOrDash(row.groundWorst, 2),
                       row.preset == "real" ? "-" : fixedOrDash(row.groundExact.blobsPerMpx, 0));
  }
  out << "(exact /Mpx: the blobs of what the preset added, its frames less the plates it was "
         "rendered on; the columns before it take every layer against plates estimated from its "
         "own frames, whose residue, moving water and compression, counts on both sides)\n";
  for (const std::string& note : report.notes) out << "note: " << note << "\n";
  return out.str();
}

void writeRealismReportCsv(const RealismReport& report, const std::string& path) {
  size_t ratioColumns = 0;
  std::string header =
      "clip,preset,typical,worst,coverage,delta_p50,delta_p90,delta_p99,streaks_per_mpx,length_p50_"
      "px,"
      "width_p50_px,peak_p90,elongation_by_light_p50,energy_p50,drop_contrast_p50,angle_deg,angle_"
      "spread_deg,delta_dark_"
      "third,delta_bright_third,temporal_correlation,frames,seconds,shutter_s,exact_worst,exact_"
      "typical,ground_blobs_per_mpx,ground_area_p50_px,ground_lifetime_frames,ground_delta_p90,"
      "ground_worst";
  for (const RealismRow& row : report.rows)
    if (!row.ratios.empty()) {
      for (const auto& [name, ratio] : row.ratios) header += ",ratio_" + name;
      ratioColumns = row.ratios.size();
      break;
    }
  writeReportCsv(path, header, [&](std::ostream& out) {
    for (const RealismRow& r : report.rows) {
      const StreakStats& s = r.stats;
      out << r.clip << "," << r.preset << "," << csvNumber(r.typical) << "," << csvNumber(r.worst);
      for (double v : {s.coverage,
                       s.deltaP50,
                       s.deltaP90,
                       s.deltaP99,
                       s.streaksPerMpx,
                       s.lengthP50Px,
                       s.widthP50Px,
                       s.peakP90,
                       s.elongationByLightP50,
                       s.energyP50CodesPx,
                       dropContrastOf(r),
                       s.angleDeg,
                       s.angleSpreadDeg,
                       s.deltaDarkThird,
                       s.deltaBrightThird,
                       s.temporalCorrelation,
                       double(s.frames),
                       r.seconds,
                       r.shutterSeconds,
                       r.exactWorst,
                       r.exactTypical,
                       r.ground.blobsPerMpx,
                       r.ground.areaP50Px,
                       r.ground.lifetimeFrames,
                       r.ground.deltaP90,
                       r.groundWorst})
        out << "," << csvNumber(v);
      for (size_t i = 0; i < ratioColumns; ++i)
        out << "," << (i < r.ratios.size() ? csvNumber(r.ratios[i].second) : "");
      out << "\n";
    }
  });
}

}  // namespace pluvia::lab
