// SyntheticSceneRenderer: one headless GL context, one vertex buffer of the scene's triangles
// and one framebuffer (RGBA32F colour, R32F z-depth in metres, 32F depth buffer for occlusion).
#include "lab/synthetic_scene.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>
#include <utility>

#include <epoxy/gl.h>
#include <fmt/format.h>

#include "geometry/camera.h"
#include "geometry/camera_path.h"
#include "gpu/egl_context.h"
#include "gpu/gl_check.h"
#include "gpu/gl_objects.h"
#include "gpu/shader_program.h"
#include "util/error.h"
#include "util/log.h"

namespace pluvia::lab {

using namespace pluvia::gpu;  // what this file measures

namespace {

// Near enough for a camera brushing past a box, far enough for any street; the z-depth
// written is exact whatever these are (they only bound what is drawn).
constexpr double kNearMeters = 0.05;
constexpr double kFarMeters = 1000.0;

// Keep in step with kSkyHorizon / kSkyZenith in shaders/synthetic_scene.frag.
constexpr std::array<float, 3> kSkyHorizonRgb = {0.70f, 0.78f, 0.88f};
constexpr std::array<float, 3> kSkyZenithRgb = {0.25f, 0.42f, 0.75f};

// Surface ids: they select the base colour and the region of noise space in the shader.
constexpr int kGroundSurface = 0;
constexpr int kLeftWallSurface = 1;
constexpr int kRightWallSurface = 2;
constexpr int kBackWallSurface = 3;
constexpr int kFirstBoxSurface = 4;

[[noreturn]] void throwSceneError(const std::string& message) {
  ErrorContext context;
  context.stage = "synthetic scene";
  throw Error(message, std::move(context));
}

struct Vertex {
  float position[3];
  float normal[3];
  float surface;
};

using Vec3 = std::array<double, 3>;

// Two triangles a-b-c, a-c-d (winding is irrelevant: culling is off).
void addQuad(std::vector<Vertex>& out, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d,
             const Vec3& normal, int surface) {
  auto vertex = [&](const Vec3& p) {
    return Vertex{{static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2])},
                  {static_cast<float>(normal[0]), static_cast<float>(normal[1]),
                   static_cast<float>(normal[2])},
                  static_cast<float>(surface)};
  };
  for (const Vec3* p : {&a, &b, &c, &a, &c, &d}) out.push_back(vertex(*p));
}

std::vector<Vertex> sceneTriangles(const SyntheticScene& scene) {
  std::vector<Vertex> v;
  const double w = scene.halfWidthMeters;
  const double zBack = scene.backWallZMeters;
  const double zOpen = scene.openEndZMeters;
  const double h = scene.wallHeightMeters;
  addQuad(v, {-w, 0, zOpen}, {w, 0, zOpen}, {w, 0, zBack}, {-w, 0, zBack}, {0, 1, 0},
          kGroundSurface);
  addQuad(v, {-w, 0, zOpen}, {-w, 0, zBack}, {-w, h, zBack}, {-w, h, zOpen}, {1, 0, 0},
          kLeftWallSurface);
  addQuad(v, {w, 0, zOpen}, {w, 0, zBack}, {w, h, zBack}, {w, h, zOpen}, {-1, 0, 0},
          kRightWallSurface);
  addQuad(v, {-w, 0, zBack}, {w, 0, zBack}, {w, h, zBack}, {-w, h, zBack}, {0, 0, 1},
          kBackWallSurface);
  for (size_t i = 0; i < scene.boxes.size(); ++i) {
    const SyntheticBox& box = scene.boxes[i];
    const double x0 = box.centerXMeters - 0.5 * box.sizeXMeters;
    const double x1 = box.centerXMeters + 0.5 * box.sizeXMeters;
    const double z0 = box.centerZMeters - 0.5 * box.sizeZMeters;
    const double z1 = box.centerZMeters + 0.5 * box.sizeZMeters;
    const double top = box.heightMeters;
    const int surface = kFirstBoxSurface + static_cast<int>(i);
    addQuad(v, {x0, 0, z1}, {x1, 0, z1}, {x1, top, z1}, {x0, top, z1}, {0, 0, 1}, surface);
    addQuad(v, {x0, 0, z0}, {x1, 0, z0}, {x1, top, z0}, {x0, top, z0}, {0, 0, -1}, surface);
    addQuad(v, {x0, 0, z0}, {x0, 0, z1}, {x0, top, z1}, {x0, top, z0}, {-1, 0, 0}, surface);
    addQuad(v, {x1, 0, z0}, {x1, 0, z1}, {x1, top, z1}, {x1, top, z0}, {1, 0, 0}, surface);
    addQuad(v, {x0, top, z0}, {x1, top, z0}, {x1, top, z1}, {x0, top, z1}, {0, 1, 0}, surface);
  }
  return v;
}

// Column-major clip-from-world of pluvia's pinhole camera. Window x = px and window y = py
// (image row, 0 at the top), so GL's row 0 is the image's top row and read-back is unflipped:
//   x_clip = (2f/W) x + (1 - 2cx/W) z,   y_clip = -(2f/H) y + (1 - 2cy/H) z,   w_clip = -z
// for a camera-space point (x, y, z), which divides to px = cx + f x / -z, py = cy - f y / -z.
std::array<float, 16> clipFromWorld(const SyntheticView& view) {
  const double W = view.width;
  const double H = view.height;
  const double f = view.focalPx;
  double clipFromCamera[4][4] = {
      {2.0 * f / W, 0.0, 1.0 - 2.0 * view.cx / W, 0.0},
      {0.0, -2.0 * f / H, 1.0 - 2.0 * view.cy / H, 0.0},
      {0.0, 0.0, -(kFarMeters + kNearMeters) / (kFarMeters - kNearMeters),
       -2.0 * kFarMeters * kNearMeters / (kFarMeters - kNearMeters)},
      {0.0, 0.0, -1.0, 0.0}};
  // cameraFromWorld = [R^T | -R^T p].
  const auto& R = view.worldFromCamera;
  const auto& p = view.positionMeters;
  double cameraFromWorld[4][4] = {};
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) cameraFromWorld[r][c] = R[c * 3 + r];
    cameraFromWorld[r][3] = -(R[0 * 3 + r] * p[0] + R[1 * 3 + r] * p[1] + R[2 * 3 + r] * p[2]);
  }
  cameraFromWorld[3][3] = 1.0;
  std::array<float, 16> out{};
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) {
      double sum = 0.0;
      for (int k = 0; k < 4; ++k) sum += clipFromCamera[r][k] * cameraFromWorld[k][c];
      out[c * 4 + r] = static_cast<float>(sum);
    }
  }
  return out;
}

struct SceneProgram {
  GlProgram program = buildProgram("synthetic_scene.vert", "synthetic_scene.frag");
  GLint sky = glGetUniformLocation(program.id(), "uSky");
  GLint clipFromWorld = glGetUniformLocation(program.id(), "uClipFromWorld");
  GLint cameraMeters = glGetUniformLocation(program.id(), "uCameraMeters");
  GLint viewAxis = glGetUniformLocation(program.id(), "uViewAxis");
  GLint worldFromCamera = glGetUniformLocation(program.id(), "uWorldFromCamera");
  GLint focalCxCy = glGetUniformLocation(program.id(), "uFocalCxCy");
};

// Every GL object, boxed so that it can be abandoned rather than deleted (see ~Impl).
struct GpuObjects {
  SceneProgram program;
  GlVertexArray vertexArray;
  GlBuffer vertices;
  GLsizei vertexCount = 0;
  GlTexture color;
  GlTexture depthMeters;
  GlTexture depthBuffer;
  GlFramebuffer framebuffer;
};

}  // namespace

SyntheticScene defaultSyntheticScene() {
  SyntheticScene scene;
  // Different sizes at different depths and on both sides, so depth varies across the frame
  // and the boxes occlude each other and the walls differently as the camera moves.
  scene.boxes = {
      {-3.0, -8.0, 1.2, 1.5, 1.0},   // low crate, left, 8 m
      {2.6, -14.0, 2.0, 2.0, 2.5},   // tall block, right, 14 m
      {-1.2, -22.0, 1.6, 1.4, 3.2},  // pillar near the middle, 22 m
      {3.4, -30.0, 1.4, 3.0, 1.8},   // long box, right, 30 m
  };
  return scene;
}

std::array<float, 3> syntheticSkyRgb(double unitUp) {
  const double t = std::sqrt(std::clamp(unitUp, 0.0, 1.0));
  std::array<float, 3> rgb{};
  for (int c = 0; c < 3; ++c) {
    rgb[c] = static_cast<float>(kSkyHorizonRgb[c] + (kSkyZenithRgb[c] - kSkyHorizonRgb[c]) * t);
  }
  return rgb;
}

SyntheticView defaultSyntheticIntrinsics(int width, int height) {
  return SyntheticView::fromCamera(
      Camera::fromFieldOfView(width, height, kSyntheticHfovDeg, 0.0, kSyntheticCameraHeightMeters));
}

std::vector<SyntheticPathKey> defaultSyntheticPath(int frameCount) {
  constexpr double kStepMeters = 0.05;
  constexpr double kDriftMetersPerFrame = 0.01;
  constexpr double kYawSpanDeg = 4.0;
  constexpr double kPitchDeg = -3.0;
  std::vector<SyntheticPathKey> keys;
  for (int i = 0; i < frameCount; ++i) {
    const double progress = frameCount > 1 ? static_cast<double>(i) / (frameCount - 1) : 0.0;
    SyntheticPathKey key;
    key.frame = i;
    key.positionMeters = {kDriftMetersPerFrame * i, kSyntheticCameraHeightMeters, -kStepMeters * i};
    key.yawDeg = kYawSpanDeg * (progress - 0.5);
    key.pitchDeg = kPitchDeg;
    keys.push_back(key);
  }
  return keys;
}

SyntheticView syntheticViewAt(const SyntheticView& intrinsics, const SyntheticPathKey& key) {
  // worldFromCamera = Ry(-yaw) Rx(pitch) Rz(-roll), as worldFromCameraRotation() in
  // geometry/camera_path.cpp, written out on plain arrays.
  const double yaw = -key.yawDeg * M_PI / 180.0;
  const double pitch = key.pitchDeg * M_PI / 180.0;
  const double roll = -key.rollDeg * M_PI / 180.0;
  using M = std::array<double, 9>;
  const M ry = {std::cos(yaw), 0, std::sin(yaw), 0, 1, 0, -std::sin(yaw), 0, std::cos(yaw)};
  const M rx = {1, 0, 0, 0, std::cos(pitch), -std::sin(pitch), 0, std::sin(pitch), std::cos(pitch)};
  const M rz = {std::cos(roll), -std::sin(roll), 0, std::sin(roll), std::cos(roll), 0, 0, 0, 1};
  auto multiply = [](const M& a, const M& b) {
    M out{};
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) {
        for (int k = 0; k < 3; ++k) out[r * 3 + c] += a[r * 3 + k] * b[k * 3 + c];
      }
    }
    return out;
  };
  SyntheticView view = intrinsics;
  view.worldFromCamera = multiply(multiply(ry, rx), rz);
  view.positionMeters = key.positionMeters;
  return view;
}

CameraPath defaultSyntheticCameraPath(int width, int height, int frameCount) {
  std::vector<std::pair<double, CameraPose>> keys;
  for (const SyntheticPathKey& key : defaultSyntheticPath(frameCount)) {
    CameraPose pose;
    pose.positionMeters =
        Eigen::Vector3d(key.positionMeters[0], key.positionMeters[1], key.positionMeters[2]);
    pose.yawDeg = key.yawDeg;
    pose.pitchDeg = key.pitchDeg;
    pose.rollDeg = key.rollDeg;
    keys.push_back({key.frame, pose});
  }
  return CameraPath::fromKeys(defaultSyntheticIntrinsics(width, height).toCamera<Camera>(), keys);
}

struct SyntheticSceneRenderer::Impl {
  // Declared first so it is destroyed last, after every GL object.
  HeadlessGlContext context;
  int width = 0;
  int height = 0;
  SyntheticScene scene;
  std::unique_ptr<GpuObjects> gpu;

  // GL objects are deleted by their owners' destructors, which needs this context current.
  ~Impl() {
    try {
      context.makeCurrent();
    } catch (const Error& error) {
      // Current on another thread: the objects go with their context in eglDestroyContext.
      log::warning(
          fmt::format("synthetic scene renderer destroyed off its thread: {}", error.what()));
      (void)gpu.release();
    }
  }
};

SyntheticSceneRenderer::SyntheticSceneRenderer(int width, int height, SyntheticScene scene)
    : impl_(std::make_unique<Impl>()) {
  GLint maxSize = 0;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxSize);
  if (width <= 0 || height <= 0 || width > maxSize || height > maxSize) {
    throwSceneError(fmt::format("cannot render the synthetic scene into {}x{} pixels (limit {})",
                                width, height, maxSize));
  }
  impl_->width = width;
  impl_->height = height;
  impl_->scene = std::move(scene);
  impl_->gpu = std::make_unique<GpuObjects>();
  GpuObjects& gpu = *impl_->gpu;

  const std::vector<Vertex> triangles = sceneTriangles(impl_->scene);
  gpu.vertexCount = static_cast<GLsizei>(triangles.size());
  gpu.vertexArray = genVertexArray();
  gpu.vertices = genBuffer();
  glBindVertexArray(gpu.vertexArray.id());
  glBindBuffer(GL_ARRAY_BUFFER, gpu.vertices.id());
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(triangles.size() * sizeof(Vertex)),
               triangles.data(), GL_STATIC_DRAW);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(Vertex),
                        reinterpret_cast<void*>(offsetof(Vertex, position)));
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, sizeof(Vertex),
                        reinterpret_cast<void*>(offsetof(Vertex, normal)));
  glEnableVertexAttribArray(2);
  glVertexAttribPointer(2, 1, GL_FLOAT, GL_FALSE, sizeof(Vertex),
                        reinterpret_cast<void*>(offsetof(Vertex, surface)));
  glBindVertexArray(0);

  gpu.color = makeTexture2D(GL_RGBA32F, width, height);
  gpu.depthMeters = makeTexture2D(GL_R32F, width, height);
  gpu.depthBuffer = makeTexture2D(GL_DEPTH_COMPONENT32F, width, height);
  gpu.framebuffer = genFramebuffer();
  glBindFramebuffer(GL_FRAMEBUFFER, gpu.framebuffer.id());
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, gpu.color.id(), 0);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D, gpu.depthMeters.id(),
                         0);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, gpu.depthBuffer.id(),
                         0);
  const GLenum drawBuffers[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
  glDrawBuffers(2, drawBuffers);
  const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE) {
    throwSceneError(fmt::format("synthetic scene framebuffer of {}x{} is incomplete (0x{:04x})",
                                width, height, status));
  }
  checkGl("creating the synthetic scene's buffers and targets");
}

SyntheticSceneRenderer::~SyntheticSceneRenderer() = default;

const SyntheticScene& SyntheticSceneRenderer::scene() const {
  return impl_->scene;
}

Image SyntheticSceneRenderer::render(const SyntheticView& view) {
  if (view.width != impl_->width || view.height != impl_->height) {
    throwSceneError(fmt::format("camera of {}x{} given to a synthetic scene renderer of {}x{}",
                                view.width, view.height, impl_->width, impl_->height));
  }
  if (!(view.focalPx > 0.0) || !std::isfinite(view.focalPx)) {
    throwSceneError(fmt::format("focal length {} px is not positive", view.focalPx));
  }
  impl_->context.makeCurrent();
  GpuObjects& gpu = *impl_->gpu;
  const int width = impl_->width;
  const int height = impl_->height;

  glBindFramebuffer(GL_FRAMEBUFFER, gpu.framebuffer.id());
  glViewport(0, 0, width, height);
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);
  const GLfloat black[4] = {0.0f, 0.0f, 0.0f, 1.0f};
  const float infinity = std::numeric_limits<float>::infinity();
  const GLfloat farDepth[4] = {infinity, 0.0f, 0.0f, 0.0f};
  glClearBufferfv(GL_COLOR, 0, black);
  glClearBufferfv(GL_COLOR, 1, farDepth);
  const GLfloat farthest = 1.0f;
  glClearBufferfv(GL_DEPTH, 0, &farthest);

  const SceneProgram& program = gpu.program;
  glUseProgram(program.program.id());
  const std::array<float, 16> clip = clipFromWorld(view);
  glUniformMatrix4fv(program.clipFromWorld, 1, GL_FALSE, clip.data());
  const auto& R = view.worldFromCamera;
  // The optical axis is camera -Z: minus the third column of worldFromCamera.
  glUniform3f(program.viewAxis, static_cast<float>(-R[2]), static_cast<float>(-R[5]),
              static_cast<float>(-R[8]));
  glUniform3f(program.cameraMeters, static_cast<float>(view.positionMeters[0]),
              static_cast<float>(view.positionMeters[1]),
              static_cast<float>(view.positionMeters[2]));
  // GL wants column-major; ask it to transpose the row-major matrix.
  const std::array<float, 9> rotation = {
      static_cast<float>(R[0]), static_cast<float>(R[1]), static_cast<float>(R[2]),
      static_cast<float>(R[3]), static_cast<float>(R[4]), static_cast<float>(R[5]),
      static_cast<float>(R[6]), static_cast<float>(R[7]), static_cast<float>(R[8])};
  glUniformMatrix3fv(program.worldFromCamera, 1, GL_TRUE, rotation.data());
  glUniform3f(program.focalCxCy, static_cast<float>(view.focalPx), static_cast<float>(view.cx),
              static_cast<float>(view.cy));
  glBindVertexArray(gpu.vertexArray.id());

  // Sky first, everywhere, without touching the depth buffer; then the scene over it.
  glDisable(GL_DEPTH_TEST);
  glUniform1i(program.sky, 1);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  glUniform1i(program.sky, 0);
  glDrawArrays(GL_TRIANGLES, 0, gpu.vertexCount);
  glBindVertexArray(0);
  checkGl("drawing the synthetic scene");

  Image image(width, height);
  std::vector<float>& depth = image.plane(kDepthPlane);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glReadBuffer(GL_COLOR_ATTACHMENT0);
  glReadPixels(0, 0, width, height, GL_RGBA, GL_FLOAT, image.rgba.data());
  glReadBuffer(GL_COLOR_ATTACHMENT1);
  glReadPixels(0, 0, width, height, GL_RED, GL_FLOAT, depth.data());
  checkGl("reading back the synthetic scene");
  return image;
}

std::string SyntheticSceneRenderer::deviceDescription() const {
  return impl_->context.deviceDescription();
}

}  // namespace pluvia::lab
