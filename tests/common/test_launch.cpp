// The launch helper's CPU backend: each pixel visited exactly once, any size, any thread count.
#include <vector>

#include "rt_catch.h"

#include "rt/atomic.h"
#include "rt/launch.h"

using namespace rt;

TEST_CASE("CPU launch visits every pixel exactly once", "[common]") {
  for (const Extent e : {Extent{1, 1}, Extent{3, 1000}, Extent{1000, 3}, Extent{257, 129}}) {
    std::vector<unsigned> counts(static_cast<std::size_t>(e.pixel_count()), 0u);
    unsigned* c = counts.data();
    for_each_pixel(Backend::cpu, e,
                   [=](int x, int y) { atomic_increment(c + y * e.width + x); });
    for (unsigned n : counts) REQUIRE(n == 1u);
  }
}

TEST_CASE("empty extents launch nothing", "[common]") {
  int calls = 0;
  for_each_pixel_cpu(Extent{0, 10}, [&](int, int) { ++calls; });
  for_each_pixel_cpu(Extent{10, 0}, [&](int, int) { ++calls; });
  CHECK(calls == 0);
}

TEST_CASE("an unresolved backend is refused", "[common]") {
  CHECK_THROWS_AS(for_each_pixel(Backend::automatic, Extent{1, 1}, [](int, int) {}), Error);
}

TEST_CASE("grid rounding", "[common]") {
  CHECK(blocks_to_cover(1, 16) == 1);
  CHECK(blocks_to_cover(16, 16) == 1);
  CHECK(blocks_to_cover(17, 16) == 2);
  CHECK(blocks_to_cover(1080, 16) == 68);
}

TEST_CASE("pixel tiles number every pixel exactly once, a warp's 8 x 4 square each",
          "[common]") {
  for (const Extent e : {Extent{1, 1}, Extent{8, 4}, Extent{9, 5}, Extent{3, 1000},
                         Extent{1000, 3}, Extent{257, 129}}) {
    const PixelTiles tiles(e.width, e.height);
    CHECK(tiles.count() % 32 == 0);
    CHECK(tiles.count() >= e.pixel_count());
    CHECK(tiles.count() < e.pixel_count() + 32LL * (tiles.tiles_x + tiles.tiles_y));
    std::vector<int> counts(static_cast<std::size_t>(e.pixel_count()), 0);
    for (long long n = 0; n < tiles.count(); ++n) {
      int x = -1, y = -1;
      if (!tiles.pixel(unsigned(n), x, y)) {
        CHECK((x >= e.width || y >= e.height)); // the tile hangs over an edge
        continue;
      }
      REQUIRE((x >= 0 && y >= 0));
      ++counts[static_cast<std::size_t>(y) * e.width + x];
      // A warp's 32 numbers stay inside one 8 x 4 square.
      CHECK(x / 8 == int(n / 32) % tiles.tiles_x);
      CHECK(y / 4 == int(n / 32) / tiles.tiles_x);
    }
    for (int c : counts) REQUIRE(c == 1);
  }
}

TEST_CASE("the 1-D CPU launch visits every index exactly once, on any thread count",
          "[common]") {
  for (const int count : {1, 63, 64 * 4 + 1, 100000}) {
    for (const int threads : {1, 2, 7}) {
      std::vector<unsigned> counts(static_cast<std::size_t>(count), 0u);
      unsigned* c = counts.data();
      for_each_index_cpu(
          static_cast<std::size_t>(count), [=](std::size_t i) { atomic_increment(c + i); },
          threads);
      for (unsigned n : counts) REQUIRE(n == 1u);
    }
    std::vector<unsigned> counts(static_cast<std::size_t>(count), 0u);
    unsigned* c = counts.data();
    for_each_index(Backend::cpu, count, [=](int i) { atomic_increment(c + i); });
    for (unsigned n : counts) REQUIRE(n == 1u);
  }
  int calls = 0;
  for_each_index(Backend::cpu, 0, [&](int) { ++calls; });
  for_each_index(Backend::cpu, -5, [&](int) { ++calls; });
  CHECK(calls == 0);
  CHECK_THROWS_AS(for_each_index(Backend::automatic, 1, [](int) {}), Error);
}
