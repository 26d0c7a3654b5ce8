// Chapter 02: three ways a frame reaches the window. See display_paths.h.
#include "display_paths.h"

#include <chrono>
#include <iostream>
#include <memory>

#include "frames.h"
#include "gl_check.h"
#include "rt/cuda_check.h"
#include "rt/device_buffer.h"
#include "rt/error.h"
#include "rt/output_file.h"
#include "rt/program_output.h"

namespace rt::ch02 {
namespace {

// The window: every resource a display path needs, re-created when the window is resized.
struct DisplayResources {
  Extent extent;
  std::unique_ptr<GlPixelBuffer> pbo;               // declared before its registration,
  std::unique_ptr<CudaGlRegistration> registration; // so destroyed after it
  std::unique_ptr<DeviceBuffer<Rgba8>> d_frame;     // the copy path's device frame
  std::vector<Rgba8> host_frame;                    // the copy and CPU paths' host frame
};

// [listing:interop_frame]
void show_frame(DisplayPath path, DisplayResources& r, Viewer& viewer, int frame) {
  switch (path) {
  case DisplayPath::interop: {
    {
      const auto mapping = r.registration->map(); // CUDA owns the PBO...
      render_frame(Backend::gpu, mapping.pixels(), r.extent, frame);
    } // ...until the mapping ends here: then GL may read it
    viewer.upload_from_pixel_buffer(r.pbo->id());
    break;
  }
  case DisplayPath::copy:
    render_frame(Backend::gpu, r.d_frame->data(), r.extent, frame);
    r.d_frame->download(r.host_frame);            // device -> host over the bus
    viewer.upload_from_host(r.host_frame.data()); // host -> device over the bus again
    break;
  case DisplayPath::cpu:
    render_frame(Backend::cpu, r.host_frame.data(), r.extent, frame);
    viewer.upload_from_host(r.host_frame.data());
    break;
  }
  viewer.present();
}
// [/listing:interop_frame]

void create_resources(DisplayResources& r, Extent extent, bool gpu, bool interop) {
  r.registration.reset(); // unregister before the buffer goes
  r.pbo.reset();
  r.extent = extent;
  r.host_frame.assign(static_cast<std::size_t>(extent.pixel_count()), Rgba8{});
  if (gpu) r.d_frame = std::make_unique<DeviceBuffer<Rgba8>>(r.host_frame.size());
  if (interop) {
    r.pbo = std::make_unique<GlPixelBuffer>(r.host_frame.size() * sizeof(Rgba8));
    r.registration = std::make_unique<CudaGlRegistration>(*r.pbo);
  }
}

// The paths `choice` names that can run: interop and copy need the GPU.
std::vector<DisplayPath> chosen_paths(const std::string& choice, bool gpu) {
  std::vector<DisplayPath> paths;
  if (gpu && (choice == "all" || choice == "interop")) paths.push_back(DisplayPath::interop);
  if (gpu && (choice == "all" || choice == "copy")) paths.push_back(DisplayPath::copy);
  if (choice == "all" || choice == "cpu") paths.push_back(DisplayPath::cpu);
  if (paths.empty()) throw UsageError("--path " + choice + " needs the GPU backend");
  return paths;
}

std::string window_title(DisplayPath path, double ms, bool vsync) {
  return "ch02 | " + std::string(path_name(path)) + " | " + std::to_string(int(1000.0 / ms)) +
         " fps, " + std::to_string(ms) + " ms | vsync " + (vsync ? "on" : "off") +
         " | P: path, V: vsync, S: screenshot, Esc: quit";
}

} // namespace

const char* path_name(DisplayPath path) {
  switch (path) {
  case DisplayPath::interop:
    return "interop: kernel writes the PBO";
  case DisplayPath::copy:
    return "GPU + copy to host + upload";
  case DisplayPath::cpu:
    return "CPU + upload";
  }
  return "?";
}

std::vector<ShownPath> show_display_paths(Viewer& viewer, Backend backend,
                                          const std::string& choice, int scripted_frames) {
  const bool gpu = backend == Backend::gpu;
  std::vector<DisplayPath> paths = chosen_paths(choice, gpu);
  DisplayResources r;
  bool interop = paths.front() == DisplayPath::interop;
  try {
    create_resources(r, viewer.size(), gpu, interop);
  } catch (const CudaError& e) {
    if (choice == "interop") throw;
    std::cout << "notice: CUDA-OpenGL interop unavailable (" << e.what()
              << "); leaving out the interop path\n";
    paths.erase(paths.begin());
    interop = false;
    create_resources(r, viewer.size(), gpu, false);
  }

  const bool scripted = scripted_frames > 0; // a fixed run for tests and benchmarks
  if (scripted) viewer.set_vsync(false);
  std::vector<std::vector<double>> frame_ms(paths.size());
  std::vector<ShownPath> shown;
  std::size_t current = 0;
  int frame = 0, frame_in_path = 0;
  auto finish_path = [&] { // what is on screen now, for the comparison with the reference
    if (frame_ms[current].empty()) return;
    shown.push_back({paths[current], summarize(frame_ms[current]), viewer.read_screen(),
                     r.extent, frame - 1, current + 1 == paths.size()});
  };

  auto last_title = std::chrono::steady_clock::now();
  for (bool running = true; running;) {
    const ViewerInput input = viewer.poll();
    if (input.quit) break;
    if (input.toggle_vsync) viewer.set_vsync(!viewer.vsync());
    if (input.resized) {
      create_resources(r, viewer.size(), gpu, interop);
      viewer.resize_texture(viewer.size());
    }
    if (input.next_path && paths.size() > 1) {
      finish_path();
      current = (current + 1) % paths.size();
    }
    const auto start = std::chrono::steady_clock::now();
    show_frame(paths[current], r, viewer, frame);
    glFinish(); // the frame is on screen: time the whole path, not just its submission
    const auto stop = std::chrono::steady_clock::now();
    frame_ms[current].push_back(
        std::chrono::duration<double, std::milli>(stop - start).count());
    ++frame;
    if (input.save) {
      const UnstagedWrites now; // the reader asked for it now, not at the end of the run
      write_output_image("ch02_screenshot_" + std::to_string(frame - 1) + ".png",
                         viewer.read_screen());
    }
    if (scripted && ++frame_in_path == scripted_frames) {
      finish_path();
      frame_in_path = 0;
      frame = 0;
      running = ++current < paths.size();
      if (!running) current = paths.size() - 1;
      continue;
    }
    if (stop - last_title > std::chrono::milliseconds(500)) {
      viewer.set_title(window_title(paths[current], frame_ms[current].back(), viewer.vsync()));
      last_title = stop;
    }
  }
  if (!scripted) finish_path();
  return shown;
}

} // namespace rt::ch02
