// Chapter 03: the interactive window. See window_loop.h.
#include "window_loop.h"

#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>
#include <vector>

#include "frames.h"
#include "orbit_controls.h"
#include "rt/cli.h"
#include "rt/cuda_check.h"
#include "rt/output_file.h"
#include "rt/program_output.h"
#include "rt/report.h"

namespace rt::ch03 {
namespace {

// The pixel buffer and its CUDA registration (GPU) or a host frame (CPU), at one size.
struct FrameTarget {
  Extent extent;
  std::unique_ptr<ch02::GlPixelBuffer> pbo;               // declared before its registration,
  std::unique_ptr<ch02::CudaGlRegistration> registration; // so destroyed after it
  std::vector<Rgba8> host;

  void create(Extent size, bool interop) {
    registration.reset(); // unregister before the buffer goes
    pbo.reset();
    extent = size;
    host.assign(interop ? 0 : static_cast<std::size_t>(size.pixel_count()), Rgba8{});
    if (interop) {
      pbo = std::make_unique<ch02::GlPixelBuffer>(size.pixel_count() * sizeof(Rgba8));
      registration = std::make_unique<ch02::CudaGlRegistration>(*pbo);
    }
  }
};

} // namespace

void add_display_options(CLI::App& app, DisplayChoice& choice) {
  ch02::add_display_flags(app, choice, "Render without a window: report and image");
  add_help_paragraph(app,
                     "Window: left mouse orbits, right/middle pans, wheel zooms, W/A/S/D/Q/E "
                     "move, R resets the camera, S saves a screenshot, V toggles vsync, Esc "
                     "quits. With --frames N the window shows N frames, writes --output and "
                     "closes.");
}

WindowResult run_window(ch02::Viewer& viewer, Backend backend, const CameraSpec& start,
                        const WindowSettings& settings, const FrameRenderer& render) {
  const bool interop = backend == Backend::gpu;
  FrameTarget target;
  target.create(viewer.size(), interop);
  OrbitControls controls(start);
  const bool scripted = settings.scripted_frames > 0;
  if (!scripted)
    viewer.set_event_handler([&](const SDL_Event& e) { controls.handle(e); });
  else
    viewer.set_vsync(false);

  std::vector<double> frame_ms;
  auto last_frame = std::chrono::steady_clock::now();
  auto last_title = last_frame;
  int frame = 0;
  for (;;) {
    const ch02::ViewerInput input = viewer.poll();
    if (input.quit) break;
    if (input.toggle_vsync) viewer.set_vsync(!viewer.vsync());
    if (input.resized) {
      target.create(viewer.size(), interop);
      viewer.resize_texture(viewer.size());
    }
    const auto start_time = std::chrono::steady_clock::now();
    if (!scripted)
      controls.update(std::chrono::duration<double>(start_time - last_frame).count());
    last_frame = start_time;
    if (interop) {
      {
        const auto mapping = target.registration->map(); // CUDA owns the buffer...
        render(backend, controls.camera(), target.extent, mapping.pixels());
      } // ...until here
      viewer.upload_from_pixel_buffer(target.pbo->id());
    } else {
      render(backend, controls.camera(), target.extent, target.host.data());
      viewer.upload_from_host(target.host.data());
    }
    viewer.present();
    glFinish(); // time the whole frame, not only its submission
    const auto stop = std::chrono::steady_clock::now();
    frame_ms.push_back(std::chrono::duration<double, std::milli>(stop - start_time).count());
    ++frame;
    if (input.save) {
      const UnstagedWrites now; // the reader asked for it now, not at the end of the run
      write_output_image(settings.screenshot_prefix + "_" + std::to_string(frame - 1) + ".png",
                         viewer.read_screen());
    }
    if (scripted && frame == settings.scripted_frames) break;
    if (stop - last_title > std::chrono::milliseconds(500)) {
      const double ms = frame_ms.back();
      const CameraSpec& c = controls.camera();
      viewer.set_title(settings.title + " | " + format_fixed(1000.0 / ms, 0) + " fps, " +
                       format_fixed(ms, 2) + " ms | eye " + format_fixed(c.eye.x, 2) + "," +
                       format_fixed(c.eye.y, 2) + "," + format_fixed(c.eye.z, 2) +
                       " | mouse: orbit/pan/zoom, WASDQE: move, R: reset, S: screenshot, "
                       "V: vsync, Esc: quit");
      last_title = stop;
    }
  }
  viewer.set_event_handler(nullptr);
  WindowResult result;
  result.path = interop ? "interop" : "host upload";
  result.frames = frame;
  if (!frame_ms.empty()) result.frame_time = summarize(frame_ms);
  result.last_screen = viewer.read_screen();
  result.camera = controls.camera();
  return result;
}

} // namespace rt::ch03
