#include "gpu/shader_program.h"

#include <sstream>
#include <vector>

#include <fmt/format.h>

#include "gpu/embedded_shaders.h"
#include "gpu/gl_check.h"
#include "gpu/rain_error.h"

namespace pluvia::gpu {
namespace {

// Deep enough for any sane nesting; stops include cycles.
constexpr int kMaxIncludeDepth = 8;

std::string_view embeddedShader(const std::string& name) {
  const auto& table = embeddedShaders();
  auto it = table.find(name);
  if (it == table.end()) throwRainError(fmt::format("no embedded shader named '{}'", name));
  return it->second;
}

// GLSL #line takes a source-string number; each included file gets its own so that messages
// like "1(12): error" point into the right file (0 is the stage file itself).
void appendWithIncludes(const std::string& name, int depth, int& nextFileNumber, std::string& out) {
  if (depth > kMaxIncludeDepth) {
    throwRainError(
        fmt::format("shader includes nest deeper than {} at '{}'", kMaxIncludeDepth, name));
  }
  const int fileNumber = nextFileNumber++;
  std::istringstream lines{std::string(embeddedShader(name))};
  std::string line;
  int lineNumber = 0;
  while (std::getline(lines, line)) {
    ++lineNumber;
    const size_t open = line.find("#include \"");
    if (open != std::string::npos && line.find_first_not_of(" \t") == open) {
      const size_t start = open + 10;
      const size_t end = line.find('"', start);
      if (end == std::string::npos) {
        throwRainError(fmt::format("{}:{}: malformed #include", name, lineNumber));
      }
      out += fmt::format("#line 1 {}\n", nextFileNumber);
      appendWithIncludes(line.substr(start, end - start), depth + 1, nextFileNumber, out);
      out += fmt::format("#line {} {}\n", lineNumber + 1, fileNumber);
      continue;
    }
    out += line;
    out += '\n';
  }
}

// The shader's text with its includes resolved, bracketed by #line directives so compiler
// messages keep their file numbers and lines.
std::string shaderSourceWithIncludes(const std::string& name) {
  std::string out;
  int nextFileNumber = 0;
  appendWithIncludes(name, 0, nextFileNumber, out);
  return out;
}

// `defines` inserted after the first line (#version), then a #line that restores numbering.
std::string withDefines(const std::string& source, const std::string& defines) {
  if (defines.empty()) return source;
  const size_t endOfVersion = source.find('\n');
  if (endOfVersion == std::string::npos) return source + "\n" + defines;
  return source.substr(0, endOfVersion + 1) + defines + "#line 2 0\n" +
         source.substr(endOfVersion + 1);
}

// Throws naming `failure` and the object's info log unless its `status` (GL_COMPILE_STATUS of a
// shader, GL_LINK_STATUS of a program) is true. getParameter and getInfoLog are the object kind's
// query functions (glGetShaderiv and glGetShaderInfoLog, or the program's).
template <class GetParameter, class GetInfoLog>
void requireStatus(GLuint id, GLenum status, GetParameter getParameter, GetInfoLog getInfoLog,
                   const std::string& failure) {
  GLint ok = GL_FALSE;
  getParameter(id, status, &ok);
  if (ok) return;
  GLint logLength = 0;
  getParameter(id, GL_INFO_LOG_LENGTH, &logLength);
  std::string log(static_cast<size_t>(std::max(logLength, 1)), '\0');
  getInfoLog(id, logLength, nullptr, log.data());
  throwRainError(fmt::format("{}: {}", failure, log.c_str()));
}

GlShader compileShader(GLenum stage, const std::string& name, const std::string& defines) {
  const std::string source = withDefines(shaderSourceWithIncludes(name), defines);
  GlShader shader(glCreateShader(stage));
  const char* text = source.c_str();
  glShaderSource(shader.id(), 1, &text, nullptr);
  glCompileShader(shader.id());
  requireStatus(shader.id(), GL_COMPILE_STATUS, glGetShaderiv, glGetShaderInfoLog,
                fmt::format("shader {} does not compile", name));
  checkGl(fmt::format("compiling {}", name));
  return shader;
}

}  // namespace

GlProgram buildProgram(const std::string& vertexName, const std::string& fragmentName,
                       const std::string& defines) {
  const GlShader vertex = compileShader(GL_VERTEX_SHADER, vertexName, defines);
  const GlShader fragment = compileShader(GL_FRAGMENT_SHADER, fragmentName, defines);
  GlProgram program(glCreateProgram());
  glAttachShader(program.id(), vertex.id());
  glAttachShader(program.id(), fragment.id());
  glLinkProgram(program.id());
  requireStatus(program.id(), GL_LINK_STATUS, glGetProgramiv, glGetProgramInfoLog,
                fmt::format("shaders {} + {} do not link", vertexName, fragmentName));
  glDetachShader(program.id(), vertex.id());
  glDetachShader(program.id(), fragment.id());
  checkGl(fmt::format("linking {} + {}", vertexName, fragmentName));
  return program;
}

}  // namespace pluvia::gpu
