#pragma once
// GL error checks: called after each major step so a failure names where it happened.
#include <string_view>

namespace pluvia::gpu {

// Throws pluvia::Error (stage "rain") naming `step` and every pending GL error.
void checkGl(std::string_view step);

}  // namespace pluvia::gpu
