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
  unsigned char* deferred; // null, or 1 where the sample comes with the stragglers (below)
  RT_HD void operator()(int i) const {
    if (deferred != nullptr && deferred[i] != 0) {
      deferred[i] = 0;
      return;
    }
    add_sample(sums[i], q.paths[i].radiance, non_finite);
  }
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
    const int p = q.queue != nullptr ? q.queue[j] : j; // no queue: the paths are the stragglers
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

// [listing:wavefront_tail]
// The stragglers beside the next sample. Their launch is one thread's longest path, the GPU
// nearly idle; when a call adds several samples, the next sample's stages can fill it. The
// stragglers' paths are copied out of the way of the next camera rays, and their pixels
// marked so that this sample's Finish leaves them to the tail's own Finish.
template <class Path> struct GatherTail {
  Queues<Path> q; // q.queue: the stragglers
  Path* tail;
  int* pixels;
  unsigned char* deferred;
  RT_HD void operator()(int j) const {
    const int p = q.queue[j];
    tail[j] = q.paths[p];
    pixels[j] = p;
    deferred[p] = 1;
  }
};
template <class Path> struct FinishTail {
  const Path* tail;
  const int* pixels;
  float4* sums;
  unsigned* non_finite;
  RT_HD void operator()(int j) const {
    add_sample(sums[pixels[j]], tail[j].radiance, non_finite);
  }
};

// The GPU: gathers the `live` stragglers of q.queue into `tail`, then on the tail's stream
// finishes them and adds them to their pixels. The default stream's next work does not wait.
template <class S, class F>
void start_tail(typename BasicWavefrontQueues<typename S::Path>::Tail& tail,
                const Queues<typename S::Path>& q, int live, const S& scene, F features,
                Strategy strategy, float4* sums, unsigned* non_finite) {
  using Path = typename S::Path;
  for_each_index(
      Backend::gpu, live,
      GatherTail<Path>{q, tail.paths.data(), tail.pixels.data(), tail.deferred.data()});
  tail.gathered.record(); // on the default stream, after the gather
  CudaStream::wait(tail.stream.get(), tail.gathered);
  const Queues<Path> stragglers{tail.paths.data(), nullptr, nullptr, nullptr,
                                nullptr,           nullptr, nullptr};
  for_each_index_on(tail.stream.get(), live,
                    Complete<S, F>{stragglers, scene, features, strategy, false}, tail.threads);
  for_each_index_on(tail.stream.get(), live,
                    FinishTail<Path>{tail.paths.data(), tail.pixels.data(), sums, non_finite});
  tail.done.record(tail.stream.get());
}
// [/listing:wavefront_tail]

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
  // On the GPU, with more than one sample and no rays to count, each sample's stragglers run
  // on a stream of their own while the next sample starts (wavefront_tail). The sums stay
  // the same bit for bit: a pixel still gets its samples in order, because each Finish waits
  // for the tail before it.
  const bool overlap = backend == Backend::gpu && samples > 1 && !count_shadow_rays;
  using Tail = typename BasicWavefrontQueues<Path>::Tail;
  if (overlap && !queues.tail)
    queues.tail = std::make_unique<Tail>(backend, straggler_bar, pixels);
  bool tail_unwaited = false; // a tail the default stream has not waited for yet
  const auto wait_for_tail = [&] {
    if (tail_unwaited) CudaStream::wait(nullptr, queues.tail->done);
    tail_unwaited = false;
  };
  WavefrontPass pass;
  for (int s = 0; s < samples; ++s) {
    bool tail_started = false;
    int current = 0; // which of the two queues holds this bounce's paths
    Queues<Path> q{queues.paths.data(),    queues.shadows.data(),  queues.hits.data(),
                   queues.queue[1].data(), queues.queue[0].data(), queues.shadow_queue.data(),
                   queues.counters.data()};
    for_each_index(backend, pixels, Generate<S>{q, scene, camera, first_sample + unsigned(s)});
    int live = pixels;
    while (live > 0) {
      if (live < straggler_bar) { // too few to fill the GPU: finish them in one launch
        q.queue = queues.queue[current].data();
        if (overlap) {     // beside the next sample
          wait_for_tail(); // the last sample's tail is done with the tail's memory
          start_tail(*queues.tail, q, live, scene, features, strategy, sums, non_finite);
          tail_started = true;
          pass.tails_beside += s + 1 < samples; // the last one has no next sample beside it
          break;
        }
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
    wait_for_tail(); // the last sample's tail adds to the sums before this sample does
    for_each_index(
        backend, pixels,
        Finish<Path>{q, sums, non_finite, overlap ? queues.tail->deferred.data() : nullptr});
    tail_unwaited = tail_unwaited || tail_started;
  }
  wait_for_tail(); // what follows on the default stream sees every sum
  return pass;
}
// [/listing:wavefront_loop]

} // namespace rt::ch11
