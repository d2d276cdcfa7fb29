#pragma once
// Builds GL programs from the shaders embedded at build time (shaders/*).
#include <string>

#include "gpu/gl_objects.h"

namespace pluvia::gpu {

// The text of an embedded shader with every `#include "name"` line replaced by that embedded
// file (recursively), bracketed by #line directives so compiler messages keep their numbers.
std::string shaderSourceWithIncludes(const std::string& name);

// Compiles and links a vertex + fragment program. Throws pluvia::Error with the info log.
GlProgram buildProgram(const std::string& vertexName, const std::string& fragmentName);

}  // namespace pluvia::gpu
