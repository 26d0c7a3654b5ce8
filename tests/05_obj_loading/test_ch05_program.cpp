// Chapter 05 tests of the program's pieces: the automatic camera keeps the whole bounding box
// in view, the pixel sample, renders of a loaded model against the float64 reference (a
// sampled render equals the same pixels of the whole image), the progress line, and the
// course's own models in assets/ (what assets/README.md says they are).
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "rt_catch.h"

#include "camera_cli.h"
#include "gpu_guard.h"
#include "index_mistakes.h"
#include "mesh_gen.h"
#include "model_render.h"
#include "obj_loader.h"
#include "progress.h"
#include "rt/device_buffer.h"
#include "rt/error.h"

using namespace rt;
using namespace rt::ch05;

namespace {

std::string asset(const std::string& file) { return std::string(RT_ASSETS_DIR) + "/" + file; }

// Where a point lands in the view cone of the spec's pinhole camera: its tangents across and
// up, to compare with the half fields of view' tangents.
struct ViewTangents {
  double across, up, ahead;
};

ViewTangents tangents_of(const CameraSpec& spec, Vec3d p) {
  const ch03::ViewBasis<double> basis = ch03::look_at(spec.eye, spec.target, spec.up);
  const Vec3d d = p - spec.eye;
  const double ahead = dot(d, basis.forward);
  return {dot(d, basis.right) / ahead, dot(d, basis.up) / ahead, ahead};
}

// Every corner of the box inside the image of `extent`, with the camera in front of all.
void check_box_in_view(Vec3f lo, Vec3f hi, const CameraSpec& spec, Extent extent) {
  const double tan_v = std::tan(spec.fov_degrees * std::numbers::pi / 360.0);
  const double tan_h = tan_v * extent.width / extent.height;
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3d p{(corner & 1 ? hi : lo).x, (corner & 2 ? hi : lo).y, (corner & 4 ? hi : lo).z};
    const ViewTangents t = tangents_of(spec, p);
    CAPTURE(corner, t.across, t.up, t.ahead, tan_h, tan_v);
    CHECK(t.ahead > 0.0);
    CHECK(std::abs(t.across) <= tan_h * (1 + 1e-12));
    CHECK(std::abs(t.up) <= tan_v * (1 + 1e-12));
  }
}

ch04::TriangleScene scene_of(ch04::Mesh mesh) {
  ch04::TriangleScene scene{std::move(mesh), {}};
  scene.object.assign(scene.mesh.triangles.size(), -1);
  return scene;
}

struct CpuFrame {
  Image image;
  std::vector<ch04::MeshPixelRecord> records;
};

CpuFrame render_cpu(TriangleVariant variant, const ch04::TriangleScene& scene,
                    const CameraSpec& spec, PixelSample sample) {
  const Extent e = sample.extent();
  CpuFrame frame{Image(e.width, e.height), std::vector<ch04::MeshPixelRecord>(e.pixel_count())};
  render_model(Backend::cpu, variant, ch04::host_view(scene.mesh), scene.object.data(),
               ch03::make_camera<float>(spec, sample.image), sample, frame.image.pixels.data(),
               frame.records.data());
  return frame;
}

} // namespace

TEST_CASE("the automatic camera keeps the whole bounding box in view", "[ch05]") {
  const Vec3f boxes[][2] = {{{-1, -1, -1}, {1, 1, 1}},
                            {{0, 0, 0}, {10, 0.1f, 0.1f}},        // a long thin rod along x
                            {{-0.5f, 0, -0.5f}, {0.5f, 8, 0.5f}}, // a tower
                            {{1e5f, 1e5f, 1e5f}, {1e5f + 2, 1e5f + 1, 1e5f + 3}},
                            {{-3e-4f, 0, 0}, {3e-4f, 1e-4f, 2e-4f}}};
  const Extent extents[] = {{1280, 720}, {720, 1280}, {100, 100}, {160, 90}};
  for (const auto& box : boxes)
    for (const Extent extent : extents)
      for (const double fov : {20.0, 40.0, 90.0, 150.0}) {
        CameraSpec spec;
        spec.fov_degrees = fov;
        const CameraSpec framed = frame_bounds(box[0], box[1], spec, extent);
        CAPTURE(box[0].x, box[1].x, extent.width, extent.height, fov);
        CHECK(framed.fov_degrees == fov);
        CHECK(framed.target == ((box[0].as<double>() + box[1].as<double>()) * 0.5));
        // From the framing direction, at the distance where the bounding sphere just fits.
        const Vec3d offset = framed.eye - framed.target;
        CHECK(length(cross(offset, k_framing_direction)) <= 1e-9 * length(offset));
        CHECK(dot(offset, k_framing_direction) > 0.0);
        CHECK_NOTHROW(ch03::validate_camera(framed));
        check_box_in_view(box[0], box[1], framed, extent);
      }
}

TEST_CASE("the automatic camera fits the sphere around the box to the narrower view",
          "[ch05]") {
  // A wide image is limited by its height, a tall one by its width: the sphere touches the
  // edges of the narrower field of view exactly.
  const Vec3f lo{-1, -2, -2}, hi{1, 2, 2};
  const double radius = 0.5 * length((hi - lo).as<double>());
  CameraSpec spec;
  spec.fov_degrees = 60.0;
  const double half = 30.0 * std::numbers::pi / 180.0;
  const CameraSpec wide = frame_bounds(lo, hi, spec, {1600, 900});
  CHECK(length(wide.eye - wide.target) == Approx(radius / std::sin(half)).epsilon(1e-12));
  const CameraSpec tall = frame_bounds(lo, hi, spec, {900, 1600});
  const double half_across = std::atan(std::tan(half) * 900.0 / 1600.0);
  CHECK(length(tall.eye - tall.target) ==
        Approx(radius / std::sin(half_across)).epsilon(1e-12));
}

TEST_CASE("framing a point, and boxes float cannot frame", "[ch05]") {
  CameraSpec spec;
  const CameraSpec point = frame_bounds({2, 3, 4}, {2, 3, 4}, spec, {160, 90});
  CHECK(point.target == Vec3d{2, 3, 4});
  CHECK_NOTHROW(ch03::validate_camera(point));
  // Near float's largest value the eye, further out than the box, is not a float.
  const float big = std::numeric_limits<float>::max();
  CHECK_THROWS_AS(frame_bounds({-big, -big, -big}, {big, big, big}, spec, {160, 90}),
                  InputError);
  // A point at 1e30: the eye one unit away rounds to the same float as the target.
  CHECK_THROWS_AS(frame_bounds({1e30f, 1e30f, 1e30f}, {1e30f, 1e30f, 1e30f}, spec, {160, 90}),
                  InputError);
}

TEST_CASE("a pixel sample: every stride-th pixel of every stride-th row", "[ch05]") {
  const PixelSample whole = sample_of({160, 90}, 160 * 90);
  CHECK(whole.stride == 1);
  CHECK(whole.extent().width == 160);
  CHECK(whole.extent().height == 90);

  const PixelSample hd = sample_of({1280, 720}, 160 * 90);
  CHECK(hd.stride == 8);
  CHECK(hd.extent().width == 160);
  CHECK(hd.extent().height == 90);
  CHECK(hd.column(0) == 4); // the middle of each 8 x 8 block
  CHECK(hd.row(89) == 716);

  for (const Extent image : {Extent{1280, 720}, Extent{481, 271}, Extent{7, 3}, Extent{1, 1}})
    for (const long long most : {1LL, 2LL, 100LL, 14'400LL}) {
      const PixelSample s = sample_of(image, most);
      const Extent e = s.extent();
      CAPTURE(image.width, image.height, most, s.stride);
      CHECK(e.pixel_count() >= 1);
      CHECK(e.pixel_count() <= std::max(most, 1LL));
      CHECK(s.column(e.width - 1) < image.width); // every sampled pixel lies in the image
      CHECK(s.row(e.height - 1) < image.height);
      CHECK(s.column(e.width - 1) + s.stride >= image.width); // and none is left out
      CHECK(s.row(e.height - 1) + s.stride >= image.height);
    }
}

TEST_CASE("a model renders as its float64 reference: no holes, no NaN", "[ch05]") {
  ObjMesh mesh = load_obj(asset("smooth_torus.obj.gz"));
  const Extent extent{96, 54};
  const CameraSpec spec = frame_bounds(mesh.bounds_min, mesh.bounds_max, {}, extent);
  const ch04::TriangleScene scene = take_scene(mesh);
  const PixelSample whole{extent, 1};
  const ch04::MeshReference reference = render_model_reference(scene, spec, whole);
  long long hits = 0;
  for (const int t : reference.triangle) hits += t >= 0 ? 1 : 0;
  CHECK(hits > extent.pixel_count() / 10); // the torus is in the picture
  CHECK(hits < extent.pixel_count());      // and so is the sky
  for (const TriangleVariant variant :
       {TriangleVariant::watertight, TriangleVariant::moller_trumbore}) {
    const CpuFrame frame = render_cpu(variant, scene, spec, whole);
    const ch04::MeshFrameError e =
        ch04::compare_with_reference(frame.image, frame.records, reference);
    CAPTURE(ch04::to_string(variant), e.pixels_differing, e.holes);
    CHECK(e.nan_pixels == 0);
    CHECK(e.pixels_differing <= extent.pixel_count() / 100);
    if (variant == TriangleVariant::watertight) CHECK(e.holes == 0);
  }
}

TEST_CASE("a sampled render is exactly those pixels of the whole image", "[ch05]") {
  const ch04::TriangleScene scene = scene_of(ch04::make_icosphere(2, {0.5, 0.2, -0.3}, 1.5));
  const Extent extent{100, 61};
  CameraSpec spec;
  spec.eye = {1.0, 2.0, 5.0};
  spec.target = {0.5, 0.2, -0.3};
  const CpuFrame whole = render_cpu(TriangleVariant::watertight, scene, spec, {extent, 1});
  for (const int stride : {2, 3, 7}) {
    const PixelSample sample{extent, stride};
    const CpuFrame part = render_cpu(TriangleVariant::watertight, scene, spec, sample);
    CAPTURE(stride);
    CHECK(part.image.pixels == sampled(whole.image.pixels, sample));
    const auto records = sampled(whole.records, sample);
    for (std::size_t i = 0; i < records.size(); ++i) {
      CHECK(part.records[i].triangle == records[i].triangle);
      CHECK((part.records[i].t == records[i].t || (std::isinf(records[i].t))));
    }
    // The reference of the sample is the sample of the whole reference.
    const ch04::MeshReference ref_whole = render_model_reference(scene, spec, {extent, 1});
    const ch04::MeshReference ref_part = render_model_reference(scene, spec, sample);
    CHECK(ref_part.image.pixels == sampled(ref_whole.image.pixels, sample));
    CHECK(ref_part.triangle == sampled(ref_whole.triangle, sample));
  }
}

TEST_CASE("the render counts finished rows for the progress line", "[ch05]") {
  const ch04::TriangleScene scene = scene_of(ch04::make_icosphere(1, {0, 0, 0}, 1.0));
  const PixelSample sample = sample_of({200, 100}, 50 * 25);
  CameraSpec spec;
  spec.eye = {0, 0, 4};
  spec.target = {0, 0, 0};
  const Extent e = sample.extent();
  Image image(e.width, e.height);
  unsigned rows_done = 0;
  render_model(Backend::cpu, TriangleVariant::watertight, ch04::host_view(scene.mesh),
               scene.object.data(), ch03::make_camera<float>(spec, sample.image), sample,
               image.pixels.data(), nullptr, &rows_done);
  CHECK(rows_done == unsigned(e.height));
  unsigned reference_rows = 0;
  render_model_reference(scene, spec, sample, &reference_rows);
  CHECK(reference_rows == unsigned(e.height));
}

TEST_CASE("progress: a line every period while a render runs, nothing for a short one",
          "[ch05]") {
  using namespace std::chrono_literals;
  std::ostringstream quick_out;
  {
    Progress quick("quick", 10, quick_out, 10s);
    *quick.rows_done() = 10;
  }
  CHECK(quick_out.str().empty());

  std::ostringstream slow_out;
  {
    Progress slow("slow render", 4, slow_out, 20ms);
    for (int row = 0; row < 4; ++row) {
      std::this_thread::sleep_for(35ms);
      __atomic_fetch_add(slow.rows_done(), 1u, __ATOMIC_RELAXED);
    }
  }
  const std::string text = slow_out.str();
  CAPTURE(text);
  CHECK_THAT(text, testing::starts_with("slow render: "));
  CHECK_THAT(text, testing::contains("% of 4 rows"));
  CHECK_THAT(text, testing::contains("slow render: done in "));
}

TEST_CASE("take_scene moves the triangles and material ids, keeps bounds and counts",
          "[ch05]") {
  ObjMesh mesh = load_obj(asset("cornell_room.obj.gz"));
  const auto triangles = mesh.geometry.triangles;
  const auto materials = mesh.material_ids;
  const Vec3f lo = mesh.bounds_min;
  const ch04::TriangleScene scene = take_scene(mesh);
  CHECK(scene.mesh.triangles.size() == triangles.size());
  CHECK(scene.object == materials);
  CHECK(mesh.bounds_min == lo);
}

TEST_CASE("index mistakes rebuild the triangles as the original loader's bugs did", "[ch05]") {
  using Triangles = std::vector<std::array<int, 3>>;
  const auto corners = [](const ch04::TriangleScene& scene) {
    Triangles out;
    for (const ch04::IndexedTriangle& t : scene.mesh.triangles)
      out.push_back({t.v0, t.v1, t.v2});
    return out;
  };
  ch04::TriangleScene loaded;
  loaded.mesh.vertices.resize(6);
  loaded.mesh.triangles = {{2, 3, 0}, {3, 1, 0}, {1, 4, 0}};
  loaded.object = {5, 6, 7};
  ch04::TriangleScene scene = loaded;
  repeat_index_mistake(scene, IndexMistake::none);
  CHECK(corners(scene) == corners(loaded));
  // One index lower; vertex 0's -1 wraps round to the last vertex.
  repeat_index_mistake(scene, IndexMistake::minus_one);
  CHECK(corners(scene) == Triangles{{1, 2, 5}, {2, 0, 5}, {0, 3, 5}});
  CHECK(scene.object == loaded.object);
  // Three vertices per triangle in file order: six vertices make two.
  scene = loaded;
  repeat_index_mistake(scene, IndexMistake::file_order);
  CHECK(corners(scene) == Triangles{{0, 1, 2}, {3, 4, 5}});
  CHECK(scene.object == std::vector<std::int32_t>{5, 6});
  CHECK(parse_index_mistake("minus-one") == IndexMistake::minus_one);
  CHECK_THROWS_AS(parse_index_mistake("off-by-two"), UsageError);
}

TEST_CASE("assets: the 100k-triangle torus knot is one closed mesh", "[ch05]") {
  const ObjMesh mesh = load_obj(asset("torus_knot_100k.obj.gz"));
  CHECK(mesh.geometry.triangles.size() == 100'000);
  CHECK(mesh.geometry.vertices.size() == 50'000);
  CHECK(mesh.normals.empty());
  CHECK(mesh.object_count == 1);
  CHECK(mesh.degenerate_triangle_count == 0);
  CHECK(ch04::count_unpaired_edges(mesh.geometry) == 0);
}

TEST_CASE("assets: the Cornell room, its materials, objects and closed parts", "[ch05]") {
  const ObjMesh mesh = load_obj(asset("cornell_room.obj.gz"));
  CHECK(mesh.material_names == std::vector<std::string>{"white", "red", "green", "light"});
  CHECK(mesh.object_count == 4); // room, light, short_block, tall_block
  REQUIRE(mesh.geometry.triangles.size() == 192 + 2 + 12 + 12);
  CHECK(mesh.bounds_min == Vec3f{-1, 0, -1});
  CHECK(mesh.bounds_max == Vec3f{1, 2, 1});
  // The room (six walls of 4 x 4 squares) and each block are closed on their own.
  const auto part = [&](int first, int count) {
    ch04::Mesh piece{mesh.geometry.vertices, {}};
    piece.triangles.assign(mesh.geometry.triangles.begin() + first,
                           mesh.geometry.triangles.begin() + first + count);
    return piece;
  };
  CHECK(ch04::count_unpaired_edges(part(0, 192)) == 0);
  CHECK(ch04::count_unpaired_edges(part(194, 12)) == 0);
  CHECK(ch04::count_unpaired_edges(part(206, 12)) == 0);
  // Triangles per material: four white walls of 32 and the blocks, a red and a green wall,
  // the light.
  std::vector<int> per_material(4, 0);
  for (const int id : mesh.material_ids) ++per_material.at(static_cast<std::size_t>(id));
  CHECK(per_material == std::vector<int>{4 * 32 + 24, 32, 32, 2});
}

TEST_CASE("assets: the smooth torus, with a normal and a texture coordinate per corner",
          "[ch05]") {
  const ObjMesh mesh = load_obj(asset("smooth_torus.obj.gz"));
  REQUIRE(mesh.geometry.triangles.size() == 4096);
  CHECK(mesh.geometry.vertices.size() == 2048);
  CHECK(mesh.normals.size() == 2048);
  CHECK(mesh.texcoords.size() == 65 * 33);
  CHECK(ch04::count_unpaired_edges(mesh.geometry) == 0);
  REQUIRE(mesh.normal_indices.size() == 4096);
  for (std::size_t i = 0; i < mesh.geometry.triangles.size(); ++i) {
    const ch04::IndexedTriangle v = mesh.geometry.triangles[i], n = mesh.normal_indices[i];
    // vn is numbered like v; each normal is unit and points away from the tube's core.
    CHECK((n.v0 == v.v0 && n.v1 == v.v1 && n.v2 == v.v2));
    CHECK(std::abs(length(mesh.normals[n.v0]) - 1.0f) < 1e-4f);
  }
  CHECK(mesh.texcoord_indices.size() == 4096);
}

TEST_CASE("GPU render of a model equals the CPU's, sampled or whole", "[ch05][gpu]") {
  RT_REQUIRE_GPU();
  ObjMesh mesh = load_obj(asset("smooth_torus.obj.gz"));
  const Extent extent{320, 180};
  const CameraSpec spec = frame_bounds(mesh.bounds_min, mesh.bounds_max, {}, extent);
  const ch04::TriangleScene scene = take_scene(mesh);
  const ch04::DeviceTriangleScene d_scene(scene);
  for (const PixelSample sample : {PixelSample{extent, 1}, sample_of(extent, 60 * 40)}) {
    const Extent e = sample.extent();
    DeviceBuffer<Rgba8> d_pixels(static_cast<std::size_t>(e.pixel_count()));
    DeviceBuffer<ch04::MeshPixelRecord> d_records(d_pixels.size());
    render_model(Backend::gpu, TriangleVariant::watertight, d_scene.view(), d_scene.object(),
                 ch03::make_camera<float>(spec, extent), sample, d_pixels.data(),
                 d_records.data());
    const std::vector<Rgba8> gpu = d_pixels.to_host();
    const CpuFrame cpu = render_cpu(TriangleVariant::watertight, scene, spec, sample);
    const ch04::MeshReference reference = render_model_reference(scene, spec, sample);
    Image gpu_image(e.width, e.height);
    gpu_image.pixels = gpu;
    const ch04::MeshFrameError error =
        ch04::compare_with_reference(gpu_image, d_records.to_host(), reference);
    CAPTURE(sample.stride, error.pixels_differing);
    CHECK(static_cast<long long>(count_differing_pixels(gpu, cpu.image.pixels)) <=
          e.pixel_count() / 200);
    CHECK(error.holes == 0);
    CHECK(error.nan_pixels == 0);
  }
}

TEST_CASE("a model too large for the GPU is refused before anything is uploaded",
          "[ch05][gpu]") {
  RT_REQUIRE_GPU();
  CHECK_NOTHROW(check_device_memory(1 << 20, "small.obj"));
  try {
    check_device_memory(std::size_t(1) << 50, "huge.obj"); // a petabyte
    FAIL("no error");
  } catch (const InputError& e) {
    CHECK_THAT(std::string(e.what()), testing::starts_with("huge.obj: needs "));
    CHECK_THAT(std::string(e.what()), testing::contains(" of GPU memory"));
  }
}
