// Common code on the GPU: the launch helper, RAII buffers and errors, and
// difference_of_products under both FMA-contraction settings.
#include <cmath>
#include <random>

#include "rt_catch.h"

#include "gpu_guard.h"
#include "rt/cuda_check.h"
#include "rt/device_buffer.h"
#include "rt/scalar.h"

std::vector<float> dop_on_gpu_default_flags(const std::vector<float>& quads);
std::vector<float> dop_on_gpu_no_fmad(const std::vector<float>& quads);

using namespace rt;

TEST_CASE("difference_of_products on the GPU equals the CPU under both FMA settings",
          "[common][gpu]") {
  RT_REQUIRE_GPU();
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.5f, 2.0f);
  std::vector<float> quads;
  for (int i = 0; i < 100000; ++i) {
    const float a = u(rng), b = u(rng);
    quads.insert(quads.end(),
                 {a, b, std::nextafter(a, 4.0f), b * (1.0f - 1e-7f * float(i % 7))});
  }
  const auto with_fma = dop_on_gpu_default_flags(quads);
  const auto without = dop_on_gpu_no_fmad(quads);
  for (std::size_t i = 0; i < with_fma.size(); ++i) {
    const float cpu = difference_of_products(quads[4 * i], quads[4 * i + 1], quads[4 * i + 2],
                                             quads[4 * i + 3]);
    REQUIRE(with_fma[i] == cpu);
    REQUIRE(without[i] == cpu);
  }
}

TEST_CASE("an absurd device allocation is a CudaError naming the size", "[common][gpu]") {
  RT_REQUIRE_GPU();
  const std::size_t huge = std::size_t(1) << 50; // a petabyte
  CHECK_THROWS_AS(DeviceBuffer<char>(huge), CudaError);
  CHECK_THROWS_WITH(DeviceBuffer<char>(huge),
                    rt::testing::contains("cudaErrorMemoryAllocation") &&
                        rt::testing::contains("1125899906842624 bytes"));
  DeviceBuffer<int> fine(16); // the failed call left no sticky error behind
  CHECK(fine.size() == 16);
}

TEST_CASE("device buffers round-trip and move", "[common][gpu]") {
  RT_REQUIRE_GPU();
  std::vector<int> host(1000);
  for (int i = 0; i < 1000; ++i) host[i] = i * i;
  DeviceBuffer<int> a{std::span<const int>(host)};
  DeviceBuffer<int> b = std::move(a);
  CHECK(a.data() == nullptr);
  CHECK(b.to_host() == host);
  CHECK_THROWS_AS(b.upload(std::span<const int>(host.data(), 10)), Error);
}
