#pragma once
// Builds GL programs from the shaders embedded at build time (shaders/*). A line
// `#include "name"` in a shader is replaced by that embedded file (recursively).
#include <string>

#include "gpu/gl_objects.h"

namespace pluvia::gpu {

// Compiles and links a vertex + fragment program. Throws pluvia::Error with the info log.
GlProgram buildProgram(const std::string& vertexName, const std::string& fragmentName);

}  // namespace pluvia::gpu
