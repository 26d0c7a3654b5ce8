// Chapter 11: the wavefront's stages (wavefront.h) as templates over the scene's view S, as
// path_kernels.cuh has the megakernel's: this chapter runs them for PathSceneView, a later
// chapter for its own view, whose start_path and shade_vertex C++ finds by S's type.
#pragma once

#include <algorithm>

#include "parallel.h"
#include "rt/cuda_check.h"
#include "rt/kernel_info.h"
#include "wavefront.h"

namespace rt::ch11 {

// The pointers every stage reads, by value into each kernel.
template <class Path> struct Queues {
  Path* paths;
  ShadowRays* shadows;
  TraceHit* hits;
  const int* queue;  // this bounce's live paths
  int* next_queue;   // filled by shade
  int* shadow_queue; // filled by shade
  unsigned* counters;
};

// [listing:wavefront_stages]
template <class S> struct Generate { // a camera ray per pixel; every path is live
  Queues<typename S::Path> q;
  S scene;
  ch03::Camera<float> camera;
  unsigned sample;
  RT_HD void operator()(int i) const {
    const int width = camera.pinhole.width;
    q.paths[i] = start_path(scene, camera, i % width, i / width, sample);
    q.next_queue[i] = i;
  }
};

template <class S> struct Extend { // the closest hit of each live path's ray
  Queues<typename S::Path> q;
  S scene;
  RT_HD void operator()(int j) const {
    q.hits[j] = ch09::trace_wide<Query::closest>(scene.tree, q.paths[q.queue[j]].ray);
  }
};

template <class S, class F> struct Shade { // shade_vertex; queue the shadow rays, survivors
  Queues<typename S::Path> q;
  S scene;
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

template <class S> struct Connect { // the shadow rays, any hit; what reaches the light joins
  Queues<typename S::Path> q;
  S scene;
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

template <class Path> struct Finish { // every path has ended: its radiance joins its pixel
  Queues<Path> q;
  float4* sums;
  unsigned* non_finite;
  RT_HD void operator()(int i) const { add_sample(sums[i], q.paths[i].radiance, non_finite); }
};
// [/listing:wavefront_stages]

// [listing:wavefront_stragglers]
// The stragglers: each path of the queue taken to its end in one thread, bounce after bounce,
// as the megakernel does: extend, shade and connect in the same order as the stages above, so
// the sums are the same bit for bit.
template <class S, class F> struct Complete {
  Queues<typename S::Path> q;
  S scene;
  F features;
  Strategy strategy;
  bool count_rays;
  RT_HD void operator()(int j) const {
    const int p = q.queue[j];
    typename S::Path path = q.paths[p]; // in registers while it runs, back when it ends
    ShadowRays shadows;
    bool alive = true;
    while (alive) {
      if (count_rays) atomic_increment(&q.counters[k_straggler_rays_traced]);
      const TraceHit hit = ch09::trace_wide<Query::closest>(scene.tree, path.ray);
      shadows.count = 0;
      alive = shade_vertex(scene, features, strategy, path, hit, shadows);
      for (int k = 0; k < shadows.count; ++k) {
        if (count_rays) atomic_increment(&q.counters[k_shadow_rays_traced]);
        if (ch09::trace_wide<Query::any>(scene.tree, shadows.ray[k]).triangle < 0)
          path.radiance += shadows.contribution[k];
      }
    }
    q.paths[p] = path;
  }
};
// [/listing:wavefront_stragglers]

// The counters after a stage, on the host.
inline void read_counters(Backend backend, const unsigned* counters,
                          unsigned (&out)[k_wavefront_counters]) {
  if (backend == Backend::gpu) {
    RT_CUDA_CHECK(cudaMemcpy(out, counters, sizeof out, cudaMemcpyDeviceToHost));
  } else {
    std::copy(counters, counters + k_wavefront_counters, out);
  }
}

// Registers per thread of the wavefront's largest stage kernel; needs a usable GPU.
template <class S, class F> int wavefront_registers_of() {
  return std::max({kernel_registers(for_each_index_kernel<Extend<S>>),
                   kernel_registers(for_each_index_kernel<Shade<S, F>>),
                   kernel_registers(for_each_index_kernel<Connect<S>>),
                   kernel_registers(for_each_index_kernel<Complete<S, F>>)});
}

// [listing:wavefront_loop]
template <class S, class F>
WavefrontPass run_wavefront(Backend backend, F features, Strategy strategy, const S& scene,
                            const ch03::Camera<float>& camera, unsigned first_sample,
                            int samples, float4* sums, unsigned* non_finite,
                            BasicWavefrontQueues<typename S::Path>& queues,
                            bool count_shadow_rays) {
  using Path = typename S::Path;
  const int pixels = static_cast<int>(queues.capacity()); // an image: at most 2^25 (cli.h)
  const int straggler_bar = std::min(k_straggler_paths, pixels / k_straggler_share);
  WavefrontPass pass;
  for (int s = 0; s < samples; ++s) {
    int current = 0; // which of the two queues holds this bounce's paths
    Queues<Path> q{queues.paths.data(),    queues.shadows.data(),  queues.hits.data(),
                   queues.queue[1].data(), queues.queue[0].data(), queues.shadow_queue.data(),
                   queues.counters.data()};
    for_each_index(backend, pixels, Generate<S>{q, scene, camera, first_sample + unsigned(s)});
    int live = pixels;
    while (live > 0) {
      if (live < straggler_bar) { // too few to fill the GPU: finish them in one launch
        q.queue = queues.queue[current].data();
        queues.counters.clear();
        for_each_index(backend, live,
                       Complete<S, F>{q, scene, features, strategy, count_shadow_rays});
        if (count_shadow_rays) {
          unsigned counts[k_wavefront_counters];
          read_counters(backend, queues.counters.data(), counts);
          pass.extended += counts[k_straggler_rays_traced];
          pass.shadow_rays += counts[k_shadow_rays_traced];
        }
        break;
      }
      q.queue = queues.queue[current].data();
      q.next_queue = queues.queue[1 - current].data();
      for_each_index(backend, live, Extend<S>{q, scene});
      queues.counters.clear();
      for_each_index(backend, live, Shade<S, F>{q, scene, features, strategy});
      unsigned counts[k_wavefront_counters];
      read_counters(backend, queues.counters.data(), counts);
      for_each_index(backend, static_cast<int>(counts[k_shadow_queue_length]),
                     Connect<S>{q, scene, count_shadow_rays});
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
    for_each_index(backend, pixels, Finish<Path>{q, sums, non_finite});
  }
  return pass;
}
// [/listing:wavefront_loop]

} // namespace rt::ch11
