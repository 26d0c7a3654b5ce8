// Chapter 11: the wavefront path tracer (Laine, Karras and Aila 2013, "Megakernels considered
// harmful"). One sample per pixel at a time, split into stages, each a kernel of its own over a
// queue of paths in memory: generate the camera rays, extend (trace every live path's ray to
// its closest hit), shade (shade_vertex: queue the shadow rays and the paths that go on), and
// connect (trace the shadow rays, any hit). Queues are compacted with atomic counters; the last
// few paths, too few to fill the GPU, are finished in one launch (the stragglers). A stage
// runs one small function over many paths that all do the same thing, where the megakernel's
// threads drift apart into different parts of one large function. The stages themselves are
// in wavefront_stages.cuh; this header holds their memory and statistics.
#pragma once

#include <memory>

#include "path_trace.h"
#include "rt/backend_array.h"
#include "shaded_render.h"

namespace rt::ch11 {

using ch06::KernelKind;

// The wavefront's counters, by slot: what a stage counts with an atomic for the host to read.
enum WavefrontCounter : int {
  k_next_queue_length = 0,     // shade: the paths that go on to the next bounce
  k_shadow_queue_length = 1,   // shade: the paths with shadow rays to trace
  k_shadow_rays_traced = 2,    // connect: the shadow rays it traced (when counted)
  k_straggler_rays_traced = 3, // complete: the rays it extended the stragglers by (counted)
  k_wavefront_counters = 4,    // how many
};

// When fewer paths are live than k_straggler_paths and than one in k_straggler_share of the
// image's, the wavefront stops launching three kernels a bounce and finishes them in one
// launch (Complete, wavefront_stages.cuh). The last bounces of an image are few paths' work,
// and a launch for each costs several microseconds whatever it holds: an H200 runs 270 000
// threads at once (132 processors of 2 048), a quarter of that is the first bar. The second
// keeps the stages for the first bounces of a small image.
inline constexpr int k_straggler_paths = 1 << 16;
inline constexpr int k_straggler_share = 8;
// Beside the next sample, the stragglers run on 128 threads per processor, each taking its
// share of them in turn: a launch of a thread per path holds registers the next sample's
// stages want. On an H200 (132 processors) 128 took 10.1 ms a sample in chapter 12's room,
// 64 10.5 ms and 256 10.6 ms, a thread per path 10.5 ms (in calls of 8 samples).
inline constexpr int k_tail_threads_per_processor = 128;

// The memory of one pass of the wavefront over an image of `pixels` pixels: a path per pixel
// and its shadow rays, the hits of the paths in the queue, and the queues themselves: 192
// bytes per pixel with this chapter's paths, 398 MB for 1920x1080, where the megakernel keeps
// the same in registers. Path is the scene's path type (PathSceneView::Path).
template <class Path> class BasicWavefrontQueues {
public:
  BasicWavefrontQueues(Backend backend, long long pixels)
      : paths(backend, pixels), shadows(backend, pixels),
        hits(backend, pixels), queue{BackendArray<int>(backend, pixels),
                                     BackendArray<int>(backend, pixels)},
        shadow_queue(backend, pixels), counters(backend, k_wavefront_counters) {}
  long long capacity() const { return static_cast<long long>(paths.size()); }

  BackendArray<Path> paths;         // path i is pixel i's
  BackendArray<ShadowRays> shadows; // the shadow rays of path i's last vertex
  BackendArray<TraceHit> hits;      // hits[j]: what queue entry j's ray found
  BackendArray<int> queue[2];       // the live paths: this bounce's, the next bounce's
  BackendArray<int> shadow_queue;   // paths with shadow rays to trace
  BackendArray<unsigned> counters;  // by WavefrontCounter

  // The stragglers of one sample, finished on a stream of their own while the next sample's
  // stages run (the GPU, a call of several samples): a copy of their paths, their pixels, and
  // a flag for each pixel whose sample they carry. Made on first use; about 10 MB.
  struct Tail {
    Tail(Backend backend, int capacity, long long pixel_count)
        : paths(backend, capacity), pixels(backend, capacity), deferred(backend, pixel_count) {
      deferred.clear();
      int device = 0, processors = 0;
      RT_CUDA_CHECK(cudaGetDevice(&device));
      RT_CUDA_CHECK(
          cudaDeviceGetAttribute(&processors, cudaDevAttrMultiProcessorCount, device));
      threads = processors * k_tail_threads_per_processor;
    }
    int threads = 0; // how many threads run the stragglers (for_each_index_on)
    BackendArray<Path> paths;
    BackendArray<int> pixels;
    BackendArray<unsigned char> deferred; // 1: the pixel's sample comes with the tail
    CudaStream stream;
    CudaEvent gathered{cudaEventDisableTiming}, done{cudaEventDisableTiming};
  };
  std::unique_ptr<Tail> tail;
};
using WavefrontQueues = BasicWavefrontQueues<PathState>;

// The wavefront's statistics of its last pass, for the report.
struct WavefrontPass {
  int bounces = 0;                 // extend stages run
  long long extended = 0;          // rays traced by extend, over every bounce
  long long shadow_rays_paths = 0; // paths queued for connect, over every bounce
  long long shadow_rays = 0;       // shadow rays traced by connect (0 unless counted)
  int tails_beside = 0;            // samples whose stragglers ran beside the next sample
};

} // namespace rt::ch11
