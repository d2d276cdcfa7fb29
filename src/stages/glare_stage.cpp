// Glare: the veil bright sources spread over the picture as the eye sees them (optics/glare.h,
// the CIE 2002 disability glare PSF), added last, after the lights, the rain and the splashes, so
// that it veils them all. Its settings are in the lights section (lights.glare); this stage has
// no section of its own.
//
// The sources: every pixel's light above 1.0 (diffuse white: a display-referred plate has none,
// its own camera's glare is already in it; halo cores, lit drops and an HDR plate's lamps do)
// moves out of its pixel into the veil, and each light the preset adds (lights.list) in front of
// the camera, inside the frame and not hidden by the scene's depth adds the veil of its
// irradiance at the camera, I(theta) exp(-beta d) / d^2. A light's own image is not drawn (the
// plate shows its lamp); only its veil is. The lamps found in the plate add none: the plate holds
// them with the bloom its camera gave them, and a second veil would light the frame twice and
// hide the rain around them.
#include <cmath>
#include <optional>

#include <fmt/format.h>

#include "optics/glare.h"
#include "stages/lights_settings.h"
#include "stages/registry.h"
#include "util/log.h"

namespace pluvia {
namespace {

// Light above this (working-space units; 1.0 is diffuse white, a display-referred file's
// maximum) glares.
constexpr float kWhite = 1.0f;
// lights.glare auto: a frame glares when all its source light, gathered at one point, would give
// a veil of lights.halo_threshold (the radiance at which a halo counts as visible) 1 deg away;
// closer in, the veil is lost in the lamp's own image and halo core. An upper bound, so a frame
// left out could show no visible veil beyond 1 deg.
constexpr double kAutoTestDeg = 1.0;
// A light behind a surface nearer than this share of its own depth is hidden (the lamps found in
// the plate sit at the depth around them).
constexpr double kOccludedBelow = 0.9;

class GlareStage : public Stage {
 public:
  explicit GlareStage(LightsSettings lights) : lights_(std::move(lights)) {}

  void prepare(ClipContext& clip) override { path_ = clip.cameraPath; }

  void process(ClipContext&, FrameContext& frame) override {
    if (lights_.glare == GlareMode::Auto && frame.lights.empty()) return;
    Image& image = frame.image;
    const Camera camera = path_.cameraAt(double(frame.frame));
    const int width = image.width, height = image.height;
    cv::Mat source(height, width, CV_32FC3, cv::Scalar::all(0));
    std::array<double, 3> flux{0, 0,
                               0};  // sum of source * pixel solid angle (1 / f^2), per channel
    for (int y = 0; y < height; ++y) {
      cv::Vec3f* row = source.ptr<cv::Vec3f>(y);
      const float* pixel = image.pixel(0, y);
      for (int x = 0; x < width; ++x, pixel += 4)
        for (int c = 0; c < 3; ++c)
          if (pixel[c] > kWhite) {
            row[x][c] = pixel[c] - kWhite;
            flux[size_t(c)] += row[x][c];
          }
    }
    const cv::Mat excess = source.clone();
    struct Splat {
      int x, y;
      cv::Vec3f value;
    };
    std::vector<Splat> splats;
    const std::vector<float>* depth = image.findPlane(kDepthPlane);
    const double f2 = camera.focalPx * camera.focalPx;
    for (const optics::LocalLight& light : frame.lights) {
      if (light.photographed) continue;  // the plate holds it with the bloom its camera gave it
      const auto& p = light.positionMeters;
      if (!(p[2] < 0.0)) continue;  // at or behind the camera
      const double z = -p[2],
                   d = std::max(std::sqrt(p[0] * p[0] + p[1] * p[1] + z * z), light.radiusMeters);
      const double px = camera.cx + camera.focalPx * p[0] / z - 0.5;
      const double py = camera.cy - camera.focalPx * p[1] / z - 0.5;
      if (!(px >= 0.0 && py >= 0.0 && px < width - 1 && py < height - 1)) continue;
      const int x0 = int(px), y0 = int(py);
      if (depth) {
        const float scene = (*depth)[size_t(std::lround(py)) * width + size_t(std::lround(px))];
        if (std::isfinite(scene) && scene < kOccludedBelow * z) continue;
      }
      // The spot's cone toward the camera: theta between its axis and light -> camera.
      const double cone = optics::spotFactor(
          light, -(light.axis[0] * p[0] + light.axis[1] * p[1] + light.axis[2] * p[2]) / d);
      const double cosOffAxis = z / d;
      // Irradiance at the camera over the pixel's solid angle (cos^3 / f^2): the radiance of a
      // pixel holding all of it.
      const double toPixel = cone * std::exp(-frame.lightsExtinctionPerMeter * d) / (d * d) * f2 /
                             (cosOffAxis * cosOffAxis * cosOffAxis);
      const double fx = px - x0, fy = py - y0;
      for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 2; ++i) {
          const double share = (i ? fx : 1 - fx) * (j ? fy : 1 - fy);
          Splat s{x0 + i, y0 + j, {}};
          for (int c = 0; c < 3; ++c) {
            const double v = std::min(1e30, share * toPixel * light.rgbIntensity[size_t(c)]);
            s.value[c] = float(v);
            flux[size_t(c)] += v;
          }
          source.at<cv::Vec3f>(s.y, s.x) += s.value;
          splats.push_back(s);
        }
    }
    const double veilAtTest =
        optics::cieGlarePsf(kAutoTestDeg) * std::max({flux[0], flux[1], flux[2]}) / f2;
    const bool glares =
        lights_.glare == GlareMode::On || veilAtTest >= lights_.haloThresholdRadiance;
    if (glares != lastGlared_) {
      log::info(
          fmt::format("glare: from frame {} {} (the sources' veil 1 deg away at most {:.3g}, "
                      "lights.halo_threshold {:g}; lights.glare {})",
                      frame.frame, glares ? "on" : "off", veilAtTest, lights_.haloThresholdRadiance,
                      lights_.glare == GlareMode::On ? "on" : "auto"));
      lastGlared_ = glares;
    }
    if (!glares) return;
    if (!pyramid_ || pyramid_->width() != width || pyramid_->height() != height ||
        std::abs(pyramid_->focalPx() / camera.focalPx - 1.0) > 1e-3)
      pyramid_.emplace(width, height, camera.focalPx);
    cv::Mat veil = pyramid_->convolve(source);
    // The light taken from the bright pixels; the lights' own images stay undrawn.
    veil -= excess;
    // The lights' own images are not drawn: their pixels take the veil just around them (taking
    // back the unscattered part of a splat of 1e7 would leave float rounding, and the fit is
    // least sure at a source's own pixel).
    for (const Splat& s : splats) {
      cv::Vec3f ring(0, 0, 0);
      int n = 0;
      for (int dy = -2; dy <= 2; ++dy)
        for (int dx = -2; dx <= 2; ++dx) {
          const int x = s.x + dx, y = s.y + dy;
          if (std::max(std::abs(dx), std::abs(dy)) < 2 || x < 0 || y < 0 || x >= width ||
              y >= height)
            continue;
          ring += veil.at<cv::Vec3f>(y, x);
          ++n;
        }
      veil.at<cv::Vec3f>(s.y, s.x) = ring / float(std::max(n, 1));
    }
    // The glare AOV (--aov glare): what the glare changed, to add to a render without it
    // (negative where bright pixels gave their light away); alpha 0 (it covers nothing).
    // Written when the frame has its planes (the render makes them when asked).
    std::array<float*, 3> aov{nullptr, nullptr, nullptr};
    if (image.findPlane("glare.R")) {
      aov = {image.plane("glare.R").data(), image.plane("glare.G").data(),
             image.plane("glare.B").data()};
      image.plane("glare.A");
    }
    for (int y = 0; y < height; ++y) {
      const cv::Vec3f* row = veil.ptr<cv::Vec3f>(y);
      float* pixel = image.pixel(0, y);
      for (int x = 0; x < width; ++x, pixel += 4)
        for (int c = 0; c < 3; ++c) {
          // Float rounding where a light's huge splat was taken back out: never below black.
          const float change = std::max(row[x][c], -pixel[c]);
          pixel[c] += change;
          if (aov[0]) aov[size_t(c)][size_t(y) * width + x] = change;
        }
    }
  }

 private:
  LightsSettings lights_;
  CameraPath path_;
  std::optional<optics::GlarePyramid> pyramid_;
  bool lastGlared_ = false;
};

}  // namespace

// Glare has no section of its own: the lights section sets it (lights.glare).
StageInfo glareStageInfo() {
  // Depth hides a light behind a surface when the frame has it (the lights stage, which places
  // the lights, reads it); the glare does not ask for it.
  return makeStageInfo(
      {.name = "glare",
       .help = "The veil bright sources spread as the eye sees them (CIE 2002 disability glare), "
               "after the rain; set in the lights section (lights.glare).",
       .inputs = {"image", "camera", "lights"},
       .outputs = {"image"}},
      lightsSettings,
      {.noOpReason = [](const LightsSettings& lights, const Preset& p) -> std::string {
         if (lights.glare == GlareMode::Off) return "lights.glare = off";
         if (lights.glare == GlareMode::Auto) {
           // Auto glares only with local lights: none when the lights stage has none.
           const std::string why = lightsStageInfo().noOpReason(p);
           if (!lights.enabled) return "lights.glare auto and the lights are disabled";
           if (!why.empty()) return "lights.glare auto and no lights (" + why + ")";
         }
         return "";
       },
       .note = [](const LightsSettings& lights, const Preset&) -> std::string {
         return lights.glare == GlareMode::On
                    ? "lights.glare on: every frame"
                    : "lights.glare auto: on the frames whose lights' veil 1 deg away could reach "
                      "lights.halo_threshold";
       },
       .create = [](const LightsSettings& lights,
                    const Preset& p) { return std::make_unique<GlareStage>(lights); }});
}

}  // namespace pluvia
