#pragma once
// The shader table that cmake/embed_shaders_run.cmake generates from shaders/ at build time:
// file name ("rain_stroke.vert") -> GLSL text, so the binary needs no shader files at run time.
#include <map>
#include <string>
#include <string_view>

namespace pluvia::gpu {

const std::map<std::string, std::string_view>& embeddedShaders();

}  // namespace pluvia::gpu
