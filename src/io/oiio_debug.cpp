#include "io/oiio_debug.h"

#include <OpenImageIO/imageio.h>

namespace pluvia {

void showOiioDebugMessages(bool show) {
  OIIO::attribute("debug", show ? 1 : 0);
}

}  // namespace pluvia
