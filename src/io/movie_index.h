#pragma once
// Whether a finished QuickTime-family movie (.mov, .mp4, .m4v: ISO base media files) is whole.
// Such a file is a run of top-level boxes (a 32-bit big-endian size, a 4-character type; size 1:
// a 64-bit size follows; size 0: to the end of the file), and it plays only with its index, the
// 'moov' box, which the muxer writes last. ffmpeg 5 exits 0 when the disk fills while it writes
// that index (its output is then the media data alone): the writer checks the file itself.
#include <string>

namespace pluvia {

// "" when `path` is not of that family or is whole: its boxes end exactly at the end of the file
// and one of them is 'moov'. Otherwise why not, in words ("no index ('moov' box): ...").
std::string movieIndexProblem(const std::string& path);

}  // namespace pluvia
