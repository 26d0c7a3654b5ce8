// OpenGL error checking (chapter 02): RT_GL_CHECK(call) runs a GL call, then asks glGetError;
// a failure throws rt::GlError naming the error and the call, like RT_CUDA_CHECK does for CUDA.
#pragma once

#include <string>

#include <GL/glew.h>

#include "rt/error.h"

namespace rt::ch02 {

class GlError : public Error {
public:
  using Error::Error;
};

const char* gl_error_name(GLenum error);
void gl_check(const char* call, const char* file, int line);

} // namespace rt::ch02

#define RT_GL_CHECK(call)                                                                      \
  do {                                                                                         \
    call;                                                                                      \
    ::rt::ch02::gl_check(#call, __FILE__, __LINE__);                                           \
  } while (false)
