#pragma once
// Proxy renders (`--proxy`): the clip read at a reduced size for quick looks.
#include <memory>

#include "io/clip_reader.h"

namespace pluvia {

// Wraps a reader so that every frame is resized by `scale` (area filter) as it is read, and
// info() gives the reduced size. Everything downstream (the camera built from the clip size,
// the per-clip analysis, every stage, the writer) then sees one consistent, smaller clip.
class ProxyClipReader : public ClipReader {
 public:
  // scale in (0, 1).
  ProxyClipReader(std::unique_ptr<ClipReader> fullSize, double scale);
  const ClipInfo& info() const override { return info_; }
  Image read(int64_t frame) override;
  void prefetch(const std::vector<int64_t>& frames) override { fullSize_->prefetch(frames); }
  // codeBits() 0: the frame is resized in the file's encoding, then converted.

 private:
  std::unique_ptr<ClipReader> fullSize_;
  ClipInfo info_;  // the full-size clip's, with the reduced width and height
};

}  // namespace pluvia
