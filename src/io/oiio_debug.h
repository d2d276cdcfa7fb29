#pragma once
// OpenImageIO's own debug lines ("OIIO DEBUG: ..."), which Debian's build prints to stderr by
// default: shown only when pluvia is asked for debug messages (-v), never under -q.
namespace pluvia {

void showOiioDebugMessages(bool show);

}  // namespace pluvia
