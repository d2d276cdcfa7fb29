#pragma once
// Builds GL programs from the shaders embedded at build time (shaders/*). A line
// `#include "name"` in a shader is replaced by that embedded file (recursively).
#include <string>

#include "gpu/gl_objects.h"

namespace pluvia::gpu {

// Compiles and links a vertex + fragment program. `defines` ("#define NAME\n" lines) go into
// both stages right after their #version line. Throws pluvia::Error with the info log.
GlProgram buildProgram(const std::string& vertexName, const std::string& fragmentName,
                       const std::string& defines = "");

}  // namespace pluvia::gpu
