#pragma once
// A depth sequence given by the user (depth.source = "file"): one depth image per plate frame,
// found by the plate's frame number, decoded to z-depth in metres along the optical axis
// (+infinity for sky, as the "depth" plane is everywhere in pluvia) and resampled to the plate.
//
// The sample read is the channel named Z, depth.Z, Y or R, in that order of preference, or the
// file's only channel. Integer files (8/16-bit PNG, TIFF) give their code values normalised to
// [0, 1] (code / 65535 for 16 bits) before the encoding is applied; float files (EXR) give their
// values as stored.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "io/sequence_pattern.h"

namespace pluvia {

enum class DepthEncoding {
  ZMeters,     // "z_m":        z = scale * v
  Inverse,     // "inverse":    z = scale / v (what depth-estimation tools write)
  Normalized,  // "normalized": z = near + v * (far - near), linear, not clamped to [0, 1]
};

// "z_m", "inverse" or "normalized"; throws pluvia::Error for any other name.
DepthEncoding depthEncodingFromName(const std::string& name);

struct DepthDecoding {
  DepthEncoding encoding = DepthEncoding::ZMeters;
  double scale = 1.0;        // z_m: metres per file unit; inverse: z = scale / v
  double nearMeters = 1.0;   // normalized: z at v = 0
  double farMeters = 100.0;  // normalized: z at v = 1
};

// The z-depth in metres of one stored value. A result that is not finite or not above 0 (NaN,
// v <= 0 for z_m, v == 0 for inverse) is sky: +infinity.
float decodeDepthValue(float value, const DepthDecoding& decoding);

// Decoded z-depth of one file, at the file's size (its display window; pixels outside the data
// window are sky).
struct DepthPlane {
  int width = 0;
  int height = 0;
  std::vector<float> meters;  // row-major, row 0 at the top
};

// Reads and decodes one depth file. Throws pluvia::Error naming the file (and frame) when it
// cannot be read or has no channel to take depth from.
DepthPlane readDepthFile(const std::string& path, const DepthDecoding& decoding,
                         std::optional<int64_t> frame);

// The plane at width x height. The same size is returned as it is; any other is resampled
// bilinearly on inverse depth (sky = 0), so that an edge between a near object and the sky gives
// an intermediate depth rather than infinity or a NaN. No prefilter when shrinking.
std::vector<float> resampleDepth(const DepthPlane& depth, int width, int height);

class DepthSequence {
 public:
  // fileOrPattern: an existing file (used for every frame), or a sequence pattern
  // ("depth.####.exr", "depth.%04d.png") whose frame numbers are the plate's.
  DepthSequence(const std::string& fileOrPattern, const DepthDecoding& decoding);

  bool singleFile() const { return !pattern_; }
  std::string pathFor(int64_t frame) const;
  // Throws pluvia::Error naming the first file among these frames' that does not exist.
  void requireFrames(const std::vector<int64_t>& frames) const;
  // The frame's z-depth in metres at width x height (see resampleDepth).
  std::vector<float> read(int64_t frame, int width, int height) const;

 private:
  std::string given_;
  std::optional<SequencePattern> pattern_;  // none: one file for every frame
  DepthDecoding decoding_;
};

}  // namespace pluvia
