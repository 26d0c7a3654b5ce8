// Chapter 11: the wavefront path tracer's stages. See wavefront.h. Compiled with -fmad=false,
// as path_render.cu is (CMakeLists.txt): the GPU's stages trace the CPU's paths bit for bit.
#define RT_NO_CONTRACTION 1
#include "wavefront.h"

#include <algorithm>

#include "parallel.h"
#include "path_dispatch.h"
#include "rt/cuda_check.h"
#include "rt/kernel_info.h"

namespace rt::ch11 {

WavefrontQueues::WavefrontQueues(Backend backend, long long pixels)
    : paths(backend, pixels), shadows(backend, pixels),
      hits(backend, pixels), queue{BackendArray<int>(backend, pixels),
                                   BackendArray<int>(backend, pixels)},
      shadow_queue(backend, pixels), counters(backend, k_wavefront_counters) {}

namespace {

// The pointers every stage reads, by value into each kernel.
struct Queues {
  PathState* paths;
  ShadowRays* shadows;
  TraceHit* hits;
  const int* queue;  // this bounce's live paths
  int* next_queue;   // filled by shade
  int* shadow_queue; // filled by shade
  unsigned* counters;
};

// [listing:wavefront_stages]
struct Generate { // a camera ray per pixel; every path is live
  Queues q;
  ch03::Camera<float> camera;
  unsigned sample;
  RT_HD void operator()(int i) const {
    const int width = camera.pinhole.width;
    q.paths[i] = start_path(camera, i % width, i / width, sample);
    q.next_queue[i] = i;
  }
};

struct Extend { // the closest hit of each live path's ray
  Queues q;
  PathSceneView scene;
  RT_HD void operator()(int j) const {
    q.hits[j] = ch09::trace_wide<Query::closest>(scene.tree, q.paths[q.queue[j]].ray);
  }
};

template <class F> struct Shade { // shade_vertex; queue the shadow rays and the survivors
  Queues q;
  PathSceneView scene;
  F features;
  Strategy strategy;
  RT_HD void operator()(int j) const {
    const int p = q.queue[j];
    ShadowRays& shadows = q.shadows[p];
    shadows.count = 0;
    if (shade_vertex(scene, features, strategy, q.paths[p], q.hits[j], shadows))
      q.next_queue[atomic_increment(&q.counters[k_next_queue_length])] = p;
    if (shadows.count > 0)
      q.shadow_queue[atomic_increment(&q.counters[k_shadow_queue_length])] = p;
  }
};

struct Connect { // the shadow rays, any hit; what reaches the light joins the path
  Queues q;
  PathSceneView scene;
  bool count_rays; // for the report's rays per path, outside the timed passes
  RT_HD void operator()(int j) const {
    const int p = q.shadow_queue[j];
    const ShadowRays& shadows = q.shadows[p];
    for (int k = 0; k < shadows.count; ++k) {
      if (count_rays) atomic_increment(&q.counters[k_shadow_rays_traced]);
      if (ch09::trace_wide<Query::any>(scene.tree, shadows.ray[k]).triangle < 0)
        q.paths[p].radiance += shadows.contribution[k];
    }
  }
};

struct Finish { // every path has ended: its radiance joins its pixel's sum
  Queues q;
  float4* sums;
  unsigned* non_finite;
  RT_HD void operator()(int i) const { add_sample(sums[i], q.paths[i].radiance, non_finite); }
};
// [/listing:wavefront_stages]

// The counters after a stage, on the host.
void read_counters(Backend backend, const unsigned* counters,
                   unsigned (&out)[k_wavefront_counters]) {
  if (backend == Backend::gpu) {
    RT_CUDA_CHECK(cudaMemcpy(out, counters, sizeof out, cudaMemcpyDeviceToHost));
  } else {
    std::copy(counters, counters + k_wavefront_counters, out);
  }
}

} // namespace

int wavefront_registers(KernelKind kernel, unsigned features) {
  int registers = 0;
  const auto take = [&](auto kernel_function) {
    registers = std::max(registers, kernel_registers(kernel_function));
  };
  with_kernel(kernel, features, [&](auto f) {
    take(for_each_index_kernel<Extend>);
    take(for_each_index_kernel<Shade<decltype(f)>>);
    take(for_each_index_kernel<Connect>);
  });
  return registers;
}

// [listing:wavefront_loop]
WavefrontPass accumulate_wavefront(Backend backend, KernelKind kernel, unsigned features,
                                   Strategy strategy, const PathSceneView& scene,
                                   const ch03::Camera<float>& camera, unsigned first_sample,
                                   int samples, float4* sums, unsigned* non_finite,
                                   WavefrontQueues& queues, bool count_shadow_rays) {
  const int pixels = static_cast<int>(queues.capacity()); // an image: at most 2^25 (cli.h)
  WavefrontPass pass;
  with_kernel(kernel, features, [&](auto f) {
    for (int s = 0; s < samples; ++s) {
      int current = 0; // which of the two queues holds this bounce's paths
      Queues q{queues.paths.data(),    queues.shadows.data(),  queues.hits.data(),
               queues.queue[1].data(), queues.queue[0].data(), queues.shadow_queue.data(),
               queues.counters.data()};
      for_each_index(backend, pixels, Generate{q, camera, first_sample + unsigned(s)});
      int live = pixels;
      while (live > 0) {
        q.queue = queues.queue[current].data();
        q.next_queue = queues.queue[1 - current].data();
        for_each_index(backend, live, Extend{q, scene});
        queues.counters.clear();
        for_each_index(backend, live, Shade<decltype(f)>{q, scene, f, strategy});
        unsigned counts[k_wavefront_counters];
        read_counters(backend, queues.counters.data(), counts);
        for_each_index(backend, static_cast<int>(counts[k_shadow_queue_length]),
                       Connect{q, scene, count_shadow_rays});
        if (count_shadow_rays) {
          read_counters(backend, queues.counters.data(), counts);
          pass.shadow_rays += counts[k_shadow_rays_traced];
        }
        ++pass.bounces;
        pass.extended += live;
        pass.shadow_rays_paths += counts[k_shadow_queue_length];
        live = static_cast<int>(counts[k_next_queue_length]);
        current = 1 - current;
      }
      for_each_index(backend, pixels, Finish{q, sums, non_finite});
    }
  });
  return pass;
}
// [/listing:wavefront_loop]

} // namespace rt::ch11
