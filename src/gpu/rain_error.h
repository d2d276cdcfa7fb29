#pragma once
// Every failure of the GPU rain module is a pluvia::Error of stage "rain".
#include <string>
#include <utility>

#include "util/error.h"

namespace pluvia::gpu {

[[noreturn]] inline void throwRainError(const std::string& message) {
  ErrorContext context;
  context.stage = "rain";
  throw Error(message, std::move(context));
}

}  // namespace pluvia::gpu
