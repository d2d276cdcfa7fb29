// buildProgram's failures name the shader and carry the driver's info log: a stage that does not
// compile, and stages that compile but do not link.
#include <gtest/gtest.h>

#include <string>

#include "gpu/egl_context.h"
#include "gpu/shader_program.h"
#include "util/error.h"

using namespace pluvia;
using namespace pluvia::gpu;

namespace {

// The message buildProgram throws with `defines`, or "" when it builds.
std::string buildError(const std::string& defines) {
  try {
    buildProgram("rain_stroke.vert", "rain_stroke.frag", defines);
  } catch (const Error& e) {
    return e.describe();
  }
  return "";
}

TEST(ShaderProgram, BuildsAndReportsCompileAndLinkFailures) {
  HeadlessGlContext context;
  EXPECT_EQ(buildError(""), "");

  const std::string compile = buildError("#error broken on purpose\n");
  EXPECT_NE(compile.find("shader rain_stroke.vert does not compile: "), std::string::npos)
      << compile;
  EXPECT_NE(compile.find("broken on purpose"), std::string::npos) << compile;  // the info log

  // Without main() each stage still compiles; the program cannot link.
  const std::string link = buildError("#define main notMain\n");
  EXPECT_NE(link.find("shaders rain_stroke.vert + rain_stroke.frag do not link: "),
            std::string::npos)
      << link;
  EXPECT_GT(link.size(),
            std::string("shaders rain_stroke.vert + rain_stroke.frag do not link: ").size())
      << "no info log: " << link;
}

}  // namespace
