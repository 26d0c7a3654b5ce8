// OpenGL error checking (chapter 02): see gl_check.h.
#include "gl_check.h"

#include <cstring>

namespace rt::ch02 {

const char* gl_error_name(GLenum error) {
  switch (error) {
  case GL_INVALID_ENUM:
    return "GL_INVALID_ENUM";
  case GL_INVALID_VALUE:
    return "GL_INVALID_VALUE";
  case GL_INVALID_OPERATION:
    return "GL_INVALID_OPERATION";
  case GL_INVALID_FRAMEBUFFER_OPERATION:
    return "GL_INVALID_FRAMEBUFFER_OPERATION";
  case GL_OUT_OF_MEMORY:
    return "GL_OUT_OF_MEMORY";
  case GL_STACK_UNDERFLOW:
    return "GL_STACK_UNDERFLOW";
  case GL_STACK_OVERFLOW:
    return "GL_STACK_OVERFLOW";
  default:
    return "unknown GL error";
  }
}

void gl_check(const char* call, const char* file, int line) {
  const GLenum error = glGetError();
  if (error == GL_NO_ERROR) return;
  while (glGetError() != GL_NO_ERROR) {
  } // GL may queue several; report the first
  const char* base = std::strrchr(file, '/');
  throw GlError(std::string(gl_error_name(error)) + " in " + call + " at " +
                (base ? base + 1 : file) + ":" + std::to_string(line));
}

} // namespace rt::ch02
