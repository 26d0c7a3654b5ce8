// Chapter 02: CUDA-OpenGL interop. Shows an animation in a window through three display paths
// (the kernel writing GL's pixel buffer directly, a GPU render copied through host memory, and
// the CPU backend) and reports each one's frame time and its pixels against the CPU reference.
// Without a display it renders headless and writes the last frame.
#include <chrono>
#include <iostream>
#include <memory>
#include <optional>
#include <vector>

#include "frames.h"
#include "gl_check.h"
#include "rt/cli.h"
#include "rt/device_buffer.h"
#include "rt/report.h"
#include "rt/timer.h"
#include "viewer.h"

namespace {

using namespace rt;
using namespace rt::ch02;

enum class DisplayPath { interop, copy, cpu };

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

struct ChapterOptions {
  CommonOptions common;
  bool headless = false;
  bool window = false;
  std::string path = "all"; // all, interop, copy, cpu
};

constexpr int k_default_frames = 120;

ReportRow error_row(std::string variant, Backend backend, const Timing& timing, Extent extent,
                    const Image& shown, int frame) {
  const Image reference = render_frame_image(Backend::cpu, extent, frame);
  const auto differing = count_differing_pixels(shown.pixels, reference.pixels);
  return {std::move(variant),
          to_string(backend),
          timing.median_ms,
          extent.pixel_count() / (timing.median_ms * 1e3),
          group_digits(static_cast<long long>(differing)) + " px differ (frame " +
              std::to_string(frame) + ")",
          {{"pixels_differing", double(differing)}}};
}

// Headless: frames into memory, timed per BENCHMARK.md; the last one is written out.
void run_headless(const ChapterOptions& options, Backend backend, Report& report) {
  const Extent extent = options.common.extent();
  const int frames = options.common.frames > 0 ? options.common.frames : k_default_frames;
  Image last(extent.width, extent.height);
  int frame = 0;
  if (backend == Backend::gpu) {
    DeviceBuffer<Rgba8> d_frame(last.pixels.size());
    const Timing kernel = time_gpu(
        [&] { render_frame(Backend::gpu, d_frame.data(), extent, frame++); }, {5, frames});
    d_frame.download(last.pixels);
    report.add_row(
        error_row("GPU frame into device memory", backend, kernel, extent, last, frame - 1));
    frame = 0;
    const Timing copied = time_gpu(
        [&] {
          render_frame(Backend::gpu, d_frame.data(), extent, frame++);
          d_frame.download(last.pixels); // over the bus into pageable host memory
        },
        {5, frames});
    report.add_row(
        error_row("GPU frame + copy to host", backend, copied, extent, last, frame - 1));
  }
  Image cpu_frame(extent.width, extent.height);
  frame = 0;
  const Timing cpu =
      time_cpu([&] { render_frame(Backend::cpu, cpu_frame.pixels.data(), extent, frame++); },
               {1, std::max(5, frames / 10)});
  report.add_row({"CPU frame",
                  "cpu",
                  cpu.median_ms,
                  extent.pixel_count() / (cpu.median_ms * 1e3),
                  "reference",
                  {{"pixels_differing", 0.0}}});
  if (!options.common.output.empty()) { // frame N-1, as the window's last frame
    write_image(options.common.output, render_frame_image(backend, extent, frames - 1));
    std::cout << "wrote " << options.common.output << " (frame " << frames - 1 << ")\n";
  }
}

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

void run_window(const ChapterOptions& options, Backend backend, Viewer& viewer,
                Report& report) {
  const bool gpu = backend == Backend::gpu;
  std::vector<DisplayPath> paths;
  if (gpu && (options.path == "all" || options.path == "interop"))
    paths.push_back(DisplayPath::interop);
  if (gpu && (options.path == "all" || options.path == "copy"))
    paths.push_back(DisplayPath::copy);
  if (options.path == "all" || options.path == "cpu") paths.push_back(DisplayPath::cpu);
  if (paths.empty()) throw UsageError("--path " + options.path + " needs the GPU backend");

  DisplayResources r;
  bool interop = paths.front() == DisplayPath::interop;
  try {
    create_resources(r, viewer.size(), gpu, interop);
  } catch (const CudaError& e) {
    if (options.path == "interop") throw;
    std::cout << "notice: CUDA-OpenGL interop unavailable (" << e.what()
              << "); leaving out the interop path\n";
    paths.erase(paths.begin());
    interop = false;
    create_resources(r, viewer.size(), gpu, false);
  }

  const bool scripted = options.common.frames > 0; // a fixed run for tests and benchmarks
  if (scripted) viewer.set_vsync(false);
  std::vector<std::vector<double>> frame_ms(paths.size());
  std::size_t current = 0;
  int frame = 0, frame_in_path = 0;
  auto finish_path = [&] { // read back what is on screen and compare it with the reference
    if (frame_ms[current].empty()) return;
    const Image screen = viewer.read_screen();
    const Timing timing = summarize(frame_ms[current]);
    if (screen.width == r.extent.width && screen.height == r.extent.height)
      report.add_row(error_row(path_name(paths[current]),
                               paths[current] == DisplayPath::cpu ? Backend::cpu : Backend::gpu,
                               timing, r.extent, screen, frame - 1));
    if (scripted && current + 1 == paths.size() && !options.common.output.empty()) {
      write_image(options.common.output, screen);
      std::cout << "wrote " << options.common.output << " (screenshot of frame " << frame - 1
                << ")\n";
    }
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
      const std::string name = "ch02_screenshot_" + std::to_string(frame - 1) + ".png";
      write_image(name, viewer.read_screen());
      std::cout << "wrote " << name << "\n";
    }
    if (scripted && ++frame_in_path == options.common.frames) {
      finish_path();
      frame_in_path = 0;
      frame = 0;
      running = ++current < paths.size();
      if (!running) current = paths.size() - 1;
      continue;
    }
    if (stop - last_title > std::chrono::milliseconds(500)) {
      const double ms = frame_ms[current].back();
      viewer.set_title("ch02 | " + std::string(path_name(paths[current])) + " | " +
                       std::to_string(int(1000.0 / ms)) + " fps, " + std::to_string(ms) +
                       " ms | vsync " + (viewer.vsync() ? "on" : "off") +
                       " | P: path, V: vsync, S: screenshot, Esc: quit");
      last_title = stop;
    }
  }
  if (!scripted) finish_path();
}

int run(const ChapterOptions& options) {
  const Backend backend = resolve_backend(options.common.backend, std::cout);
  Report report("Chapter 02: CUDA-OpenGL interop", "Mpix/s", "CPU reference");
  report.add_context("device", describe_backend(backend));
  report.add_context("image", std::to_string(options.common.width) + "x" +
                                  std::to_string(options.common.height));

  std::unique_ptr<Viewer> viewer;
  if (!options.headless) {
    try {
      viewer =
          std::make_unique<Viewer>(options.common.extent(), "ch02: CUDA-OpenGL interop", true);
    } catch (const DisplayError& e) {
      if (options.window) throw;
      std::cout << "notice: " << e.what() << "; rendering headless\n";
    }
  }
  if (viewer) {
    report.add_context("mode", "window (frame time: render + upload + draw, glFinish)");
    run_window(options, backend, *viewer, report);
  } else {
    report.add_context("mode", "headless (GPU: CUDA events; CPU: steady clock)");
    run_headless(options, backend, report);
  }
  report.print(std::cout);
  if (!options.common.json.empty()) report.write_json(options.common.json);
  for (const ReportRow& row : report.rows())
    if (row.metrics.at(0).second != 0)
      throw Error(row.variant + ": the frame differs from the CPU's");
  return 0;
}

} // namespace

int main(int argc, char** argv) {
  CLI::App app{"Chapter 02: CUDA-OpenGL interop, a window and its headless twin",
               "ch02_pbo_interop"};
  ChapterOptions options;
  options.common.width = 1280;
  options.common.height = 720;
  options.common.output = "ch02_pbo_interop.png";
  add_common_options(app, options.common);
  auto* headless = app.add_flag("--headless", options.headless,
                                "Render without a window and write the last frame");
  app.add_flag("--window", options.window, "Open the window (an error if there is no display)")
      ->excludes(headless);
  app.add_option("--path", options.path, "Display path(s) in the window")
      ->check(CLI::IsMember({"all", "interop", "copy", "cpu"}))
      ->capture_default_str();
  app.footer("Window keys: Esc quits, S saves a screenshot, V toggles vsync, P changes the "
             "display path. With --frames N the window runs N frames per path and closes.");
  return run_main(app, argc, argv, [&] {
    if (!options.common.output.empty()) check_image_path(options.common.output);
    return run(options);
  });
}
