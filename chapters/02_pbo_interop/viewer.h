// Chapter 02: the viewer. An SDL2 window with an OpenGL context that shows one RGBA8 texture,
// filled either from a pixel buffer object (the CUDA interop path) or from host memory. Later
// chapters open it with --window.
#pragma once

#include <functional>
#include <string>

#include <GL/glew.h>

#include "rt/error.h"
#include "rt/image.h"
#include "rt/launch.h"

struct SDL_Window;
union SDL_Event;

namespace rt::ch02 {

// No display to open a window on, or no usable OpenGL context: the program can go headless.
class DisplayError : public Error {
public:
  using Error::Error;
};

// True when the environment names a display (X11's DISPLAY or Wayland's WAYLAND_DISPLAY).
bool display_available();

struct ViewerInput {
  bool quit = false;         // Esc or the window's close button
  bool save = false;         // S: save a screenshot
  bool toggle_vsync = false; // V
  bool next_path = false;    // P: next display path
  bool resized = false;      // the window changed size; see Viewer::size()
};

class Viewer {
public:
  // Opens a window of the image's size; throws DisplayError when there is no display or no
  // OpenGL 2.1 context with pixel buffer objects and framebuffer blits.
  Viewer(Extent image, const std::string& title, bool vsync);
  ~Viewer();
  Viewer(const Viewer&) = delete;
  Viewer& operator=(const Viewer&) = delete;

  Extent size() const { return size_; }
  ViewerInput poll();
  // Every event poll() sees is also handed to `handler` (later chapters steer a camera with
  // it).
  void set_event_handler(std::function<void(const SDL_Event&)> handler) {
    event_handler_ = std::move(handler);
  }
  void set_title(const std::string& title);
  void set_vsync(bool on);
  bool vsync() const { return vsync_; }
  // Re-creates the texture at the window's new size (after ViewerInput::resized).
  void resize_texture(Extent size);

  // Fills the texture from a pixel buffer object bound as GL_PIXEL_UNPACK_BUFFER: a copy
  // inside GPU memory, no trip over the bus.
  void upload_from_pixel_buffer(GLuint pbo);
  // Fills the texture from host memory: the pixels cross the bus to the GPU.
  void upload_from_host(const Rgba8* pixels);
  // Draws the texture into the window (row 0 at the top) and swaps buffers.
  void present();
  // Reads back what the window shows, row 0 at the top.
  Image read_screen() const;

private:
  void draw() const; // the texture into the back buffer
  void release();

  SDL_Window* window_ = nullptr;
  void* context_ = nullptr; // SDL_GLContext
  GLuint texture_ = 0;
  GLuint framebuffer_ = 0; // a read framebuffer with the texture attached, for the blit
  Extent size_;
  bool vsync_ = true;
  std::function<void(const SDL_Event&)> event_handler_;
};

} // namespace rt::ch02
