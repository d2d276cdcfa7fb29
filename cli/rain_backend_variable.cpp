#include <cstdlib>
#include <optional>
#include <string>

#include <fmt/format.h>

#include "gpu/rain_renderer.h"
#include "process_variables.h"
#include "util/error.h"

namespace pluvia {

std::string processVariable(const char* name) {
  const char* value = std::getenv(name);
  return value ? value : "";
}

void applyRainBackendVariable() {
  const std::string name = processVariable("PLUVIA_RAIN_BACKEND");
  if (name.empty()) return;
  const std::optional<gpu::RainBackend> backend = gpu::rainBackendNamed(name);
  if (!backend)
    throw Error(fmt::format("PLUVIA_RAIN_BACKEND is '{}': use auto, egl or cpu", name), {"rain"});
  gpu::setRainBackend(*backend);
}

}  // namespace pluvia
