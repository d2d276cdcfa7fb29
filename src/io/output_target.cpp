#include "io/output_target.h"

namespace pluvia {

OutputTarget OutputTarget::classify(const std::string& path) {
  OutputTarget target;
  target.path = path;
  if (isMovieExtension(path)) {
    target.kind = Kind::Movie;
  } else if ((target.pattern = SequencePattern::parse(path))) {
    target.kind = Kind::Sequence;
  }
  return target;
}

}  // namespace pluvia
