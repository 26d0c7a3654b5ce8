// Chapter 02: the viewer. See viewer.h.
#include "viewer.h"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>

#include <unistd.h>

#include <SDL.h>

#include "gl_check.h"

namespace rt::ch02 {

bool display_available() {
  const char* x11 = std::getenv("DISPLAY");
  const char* wayland = std::getenv("WAYLAND_DISPLAY");
  return (x11 != nullptr && *x11 != '\0') || (wayland != nullptr && *wayland != '\0');
}

namespace {

std::string environment(const char* name) {
  const char* value = std::getenv(name);
  return value != nullptr ? value : "";
}

// The display the environment names, for messages: "the X display ':99' (DISPLAY)".
std::string named_display() {
  const std::string x11 = environment("DISPLAY"), wayland = environment("WAYLAND_DISPLAY");
  std::string named;
  if (!x11.empty()) named = "the X display '" + x11 + "' (DISPLAY)";
  if (!wayland.empty())
    named += (named.empty() ? "" : " or ") + ("the Wayland display '" + wayland + "'");
  return named;
}

// Runs `step` with stderr going to a temporary file, and returns the first line written there.
// SDL probes its video drivers, and the libraries under them (libwayland, Xlib) print their own
// complaints while it does ("XDG_RUNTIME_DIR is invalid or not set"), whether or not a driver
// then works. The program's one line names the display instead; the noise goes into it only
// when opening fails.
std::string first_stderr_line_of(const std::function<void()>& step) {
  std::fflush(stderr);
  std::FILE* capture = std::tmpfile();
  const int saved = capture != nullptr ? ::dup(STDERR_FILENO) : -1;
  if (saved < 0 || ::dup2(::fileno(capture), STDERR_FILENO) < 0) {
    if (saved >= 0) ::close(saved);
    if (capture != nullptr) std::fclose(capture);
    step(); // no capture possible: the noise stays, the program still works
    return {};
  }
  step();
  std::fflush(stderr);
  ::dup2(saved, STDERR_FILENO);
  ::close(saved);
  std::rewind(capture);
  char line[256] = {};
  std::string first;
  if (std::fgets(line, sizeof line, capture) != nullptr) first = line;
  std::fclose(capture);
  while (!first.empty() && (first.back() == '\n' || first.back() == '\r')) first.pop_back();
  return first;
}

} // namespace

Viewer::Viewer(Extent image, const std::string& title, bool vsync) : size_(image) {
  if (!display_available())
    throw DisplayError("no display (neither DISPLAY nor WAYLAND_DISPLAY is set)");
  // With only one kind of display named, SDL is told which driver to use, so that it does not
  // probe the other (unless the reader chose one with SDL_VIDEODRIVER).
  const bool x11 = !environment("DISPLAY").empty(),
             wayland = !environment("WAYLAND_DISPLAY").empty();
  if (environment("SDL_VIDEODRIVER").empty() && x11 != wayland)
    SDL_SetHint(SDL_HINT_VIDEODRIVER, x11 ? "x11" : "wayland");
  int status = 0;
  const std::string noise = first_stderr_line_of([&] { status = SDL_Init(SDL_INIT_VIDEO); });
  const std::string aside = noise.empty() ? "" : " (it said: " + noise + ")";
  if (status != 0)
    throw DisplayError("cannot open " + named_display() + ": SDL: " + SDL_GetError() + aside);
  // When the named display cannot be reached, SDL falls back to drivers that show nothing
  // (offscreen, dummy): that is no display either.
  const std::string driver = SDL_GetCurrentVideoDriver() ? SDL_GetCurrentVideoDriver() : "";
  if (driver != "x11" && driver != "wayland") {
    SDL_Quit();
    throw DisplayError("cannot open " + named_display() + ": SDL found only its '" + driver +
                       "' video driver" + aside);
  }
  window_ =
      SDL_CreateWindow(title.c_str(), SDL_WINDOWPOS_CENTERED, SDL_WINDOWPOS_CENTERED,
                       image.width, image.height, SDL_WINDOW_OPENGL | SDL_WINDOW_RESIZABLE);
  if (window_ == nullptr) {
    const std::string reason = SDL_GetError();
    SDL_Quit();
    throw DisplayError("cannot create a window: SDL: " + reason);
  }
  context_ = SDL_GL_CreateContext(window_);
  if (context_ == nullptr) {
    const std::string reason = SDL_GetError();
    SDL_DestroyWindow(window_);
    SDL_Quit();
    throw DisplayError("no OpenGL context: SDL: " + reason);
  }
  try {
    glewExperimental = GL_TRUE;
    const GLenum glew = glewInit();
    // GLEW 2.2 reports GLEW_ERROR_NO_GLX_DISPLAY under EGL-only setups; GL still works if the
    // entry points below were found.
    if (glew != GLEW_OK && glew != GLEW_ERROR_NO_GLX_DISPLAY)
      throw DisplayError(std::string("GLEW: ") +
                         reinterpret_cast<const char*>(glewGetErrorString(glew)));
    if (!glGenBuffers || !glBlitFramebuffer || !glGenFramebuffers)
      throw DisplayError("the OpenGL context lacks pixel buffer objects or framebuffer blits "
                         "(OpenGL 3.0 needed)");
    glGetError(); // glewInit can leave GL_INVALID_ENUM behind on core profiles
    set_vsync(vsync);
    resize_texture(image);
  } catch (...) {
    release();
    throw;
  }
}

Viewer::~Viewer() { release(); }

void Viewer::release() {
  if (framebuffer_ != 0) glDeleteFramebuffers(1, &framebuffer_);
  if (texture_ != 0) glDeleteTextures(1, &texture_);
  framebuffer_ = texture_ = 0;
  if (context_ != nullptr) SDL_GL_DeleteContext(context_);
  if (window_ != nullptr) SDL_DestroyWindow(window_);
  if (context_ != nullptr || window_ != nullptr) SDL_Quit();
  context_ = nullptr;
  window_ = nullptr;
}

ViewerInput Viewer::poll() {
  ViewerInput input;
  SDL_Event event;
  while (SDL_PollEvent(&event)) {
    if (event_handler_) event_handler_(event);
    if (event.type == SDL_QUIT) input.quit = true;
    if (event.type == SDL_KEYDOWN) {
      switch (event.key.keysym.sym) {
      case SDLK_ESCAPE:
        input.quit = true;
        break;
      case SDLK_s:
        input.save = true;
        break;
      case SDLK_v:
        input.toggle_vsync = true;
        break;
      case SDLK_p:
        input.next_path = true;
        break;
      default:
        break;
      }
    }
    if (event.type == SDL_WINDOWEVENT && event.window.event == SDL_WINDOWEVENT_SIZE_CHANGED) {
      input.resized = true;
      size_ = {event.window.data1, event.window.data2};
    }
  }
  return input;
}

void Viewer::set_title(const std::string& title) { SDL_SetWindowTitle(window_, title.c_str()); }

void Viewer::set_vsync(bool on) {
  // Some drivers refuse to change the swap interval; the window then keeps what it has.
  if (SDL_GL_SetSwapInterval(on ? 1 : 0) == 0) vsync_ = on;
}

void Viewer::resize_texture(Extent size) {
  size_ = size;
  if (framebuffer_ == 0) RT_GL_CHECK(glGenFramebuffers(1, &framebuffer_));
  if (texture_ != 0) RT_GL_CHECK(glDeleteTextures(1, &texture_));
  RT_GL_CHECK(glGenTextures(1, &texture_));
  RT_GL_CHECK(glBindTexture(GL_TEXTURE_2D, texture_));
  RT_GL_CHECK(glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST));
  RT_GL_CHECK(glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST));
  RT_GL_CHECK(glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, size.width, size.height, 0, GL_RGBA,
                           GL_UNSIGNED_BYTE, nullptr));
  RT_GL_CHECK(glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer_));
  RT_GL_CHECK(glFramebufferTexture2D(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D,
                                     texture_, 0));
  if (glCheckFramebufferStatus(GL_READ_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw GlError("the texture cannot be attached to a framebuffer for display");
  RT_GL_CHECK(glBindFramebuffer(GL_READ_FRAMEBUFFER, 0));
  RT_GL_CHECK(glPixelStorei(GL_UNPACK_ALIGNMENT, 4));
  RT_GL_CHECK(glPixelStorei(GL_PACK_ALIGNMENT, 4));
}

// [listing:upload_from_pbo]
void Viewer::upload_from_pixel_buffer(GLuint pbo) {
  // With a buffer bound to GL_PIXEL_UNPACK_BUFFER, the last argument of glTexSubImage2D is an
  // offset into that buffer, not a host pointer: the copy stays in GPU memory.
  RT_GL_CHECK(glBindBuffer(GL_PIXEL_UNPACK_BUFFER, pbo));
  RT_GL_CHECK(glBindTexture(GL_TEXTURE_2D, texture_));
  RT_GL_CHECK(glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, size_.width, size_.height, GL_RGBA,
                              GL_UNSIGNED_BYTE, nullptr));
  RT_GL_CHECK(glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0));
}
// [/listing:upload_from_pbo]

void Viewer::upload_from_host(const Rgba8* pixels) {
  RT_GL_CHECK(glBindTexture(GL_TEXTURE_2D, texture_));
  RT_GL_CHECK(glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, size_.width, size_.height, GL_RGBA,
                              GL_UNSIGNED_BYTE, pixels));
}

void Viewer::present() {
  draw();
  SDL_GL_SwapWindow(window_);
}

void Viewer::draw() const {
  // Our row 0 is the top of the image, GL's is the bottom: the blit flips by swapping the
  // destination's y bounds. GL_NEAREST keeps pixels exact when the sizes match.
  RT_GL_CHECK(glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer_));
  RT_GL_CHECK(glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0));
  int window_w = 0, window_h = 0;
  SDL_GL_GetDrawableSize(window_, &window_w, &window_h);
  RT_GL_CHECK(glViewport(0, 0, window_w, window_h));
  RT_GL_CHECK(glBlitFramebuffer(0, 0, size_.width, size_.height, 0, window_h, window_w, 0,
                                GL_COLOR_BUFFER_BIT, GL_NEAREST));
  RT_GL_CHECK(glBindFramebuffer(GL_READ_FRAMEBUFFER, 0));
}

Image Viewer::read_screen() const {
  int window_w = 0, window_h = 0;
  SDL_GL_GetDrawableSize(window_, &window_w, &window_h);
  Image image(window_w, window_h);
  std::vector<Rgba8> bottom_up(image.pixels.size());
  // After a swap the back buffer's contents are undefined, and reading the front buffer is
  // unreliable on many systems: draw the frame into the back buffer again and read that.
  draw();
  RT_GL_CHECK(glReadBuffer(GL_BACK));
  RT_GL_CHECK(
      glReadPixels(0, 0, window_w, window_h, GL_RGBA, GL_UNSIGNED_BYTE, bottom_up.data()));
  for (int y = 0; y < window_h; ++y)
    std::memcpy(&image.at(0, y), &bottom_up[std::size_t(window_h - 1 - y) * window_w],
                sizeof(Rgba8) * std::size_t(window_w));
  return image;
}

} // namespace rt::ch02
