#pragma once
// COLMAP's dense depth maps (stereo/depth_maps/<image>.{geometric,photometric}.bin), for the day
// patch_match_stereo runs here (it needs CUDA, which this COLMAP lacks) or the maps come from a
// GPU machine.
//
// Format (COLMAP src/mvs/mat.h, Mat<float>::Read/Write): an ASCII header "width&height&channels&"
// followed directly by width * height * channels float32 little-endian values, stored channel by
// channel, each channel row-major (value(row, col, c) = data[c * width * height + row * width +
// col]). Depth maps have one channel; 0 marks pixels without an estimate. Depths are z along the
// optical axis in model units, on the undistorted image (its size may differ from the frame's).
#include <filesystem>
#include <string>
#include <vector>

namespace pluvia::sfm {

struct ColmapArray {
  int width = 0;
  int height = 0;
  int channels = 0;
  std::vector<float> values;  // COLMAP's layout, see above
};

// Throws pluvia::Error naming the file on a bad header or short data.
ColmapArray readColmapArray(const std::filesystem::path& path);
void writeColmapArray(const std::filesystem::path& path, const ColmapArray& array);

// <workspace>/stereo/depth_maps/<imageName>.geometric.bin (or .photometric.bin).
std::filesystem::path colmapDepthMapPath(const std::filesystem::path& workspace,
                                         const std::string& imageName, bool geometric = true);

// A one-channel depth map as metric z-depth (row-major, width * height): model depth times
// metersPerUnit (SfmReconstruction::modelToWorld.scale; depth is unchanged by the world's
// rotation and translation). Pixels without an estimate (0 or negative) become NaN, not +inf:
// a hole is not sky.
std::vector<float> importColmapDepthMeters(const std::filesystem::path& path, double metersPerUnit,
                                           int* width = nullptr, int* height = nullptr);

}  // namespace pluvia::sfm
