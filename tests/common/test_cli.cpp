// The shared command line: defaults, and bad values refused with a clear error.
#include <algorithm>
#include <sstream>
#include <vector>

#include "rt_catch.h"

#include "rt/cli.h"
#include "rt/error.h"

using namespace rt;

namespace {

struct Parsed {
  int exit_code;
  CommonOptions options;
  std::string err;
};

Parsed parse(std::vector<std::string> args) {
  CLI::App app{"test", "prog"};
  Parsed p{0, {}, {}};
  add_common_options(app, p.options);
  args.insert(args.begin(), "prog");
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  std::ostringstream err;
  auto* old = std::cerr.rdbuf(err.rdbuf());
  p.exit_code = run_main(app, int(argv.size()), argv.data(), [] { return 0; });
  std::cerr.rdbuf(old);
  p.err = err.str();
  return p;
}

} // namespace

TEST_CASE("common options parse", "[common]") {
  const Parsed p = parse({"--width", "640", "--height", "480", "--backend", "cpu", "--frames",
                          "3", "--json", "r.json", "-o", "x.pfm"});
  CHECK(p.exit_code == 0);
  CHECK(p.options.width == 640);
  CHECK(p.options.height == 480);
  CHECK(p.options.backend == Backend::cpu);
  CHECK(p.options.frames == 3);
  CHECK(p.options.json == "r.json");
  CHECK(p.options.output == "x.pfm");
  CHECK(parse({}).options.backend == Backend::automatic);
}

TEST_CASE("bad command-line values are one clear error line and exit code 2", "[common]") {
  for (const auto& args : std::vector<std::vector<std::string>>{{"--width", "0"},
                                                                {"--height", "-5"},
                                                                {"--width", "100000"},
                                                                {"--width", "abc"},
                                                                {"--backend", "tpu"},
                                                                {"--frames", "0"},
                                                                {"--no-such-option"}}) {
    CAPTURE(args);
    const Parsed p = parse(args);
    CHECK(p.exit_code == 2);
    CHECK_THAT(p.err, rt::testing::starts_with("prog: error: "));
    CHECK(std::count(p.err.begin(), p.err.end(), '\n') == 1);
  }
}

TEST_CASE("errors thrown by the program body become exit codes", "[common]") {
  CLI::App app{"test", "prog"};
  char name[] = "prog";
  char* argv[] = {name};
  std::ostringstream err;
  auto* old = std::cerr.rdbuf(err.rdbuf());
  CHECK(run_main(app, 1, argv, []() -> int { throw InputError("bad mesh 'x.obj'"); }) == 1);
  CHECK(run_main(app, 1, argv, []() -> int { throw UsageError("bad flag"); }) == 2);
  CHECK(run_main(app, 1, argv, []() -> int { throw std::bad_alloc(); }) == 1);
  std::cerr.rdbuf(old);
  CHECK_THAT(err.str(), rt::testing::contains("prog: error: bad mesh 'x.obj'\n"));
  CHECK_THAT(err.str(), rt::testing::contains("prog: error: out of host memory\n"));
}

TEST_CASE("backend names", "[common]") {
  CHECK(parse_backend("auto") == Backend::automatic);
  CHECK(parse_backend("gpu") == Backend::gpu);
  CHECK(parse_backend("cpu") == Backend::cpu);
  CHECK_THROWS_AS(parse_backend("GPU"), UsageError);
  CHECK(std::string(to_string(Backend::gpu)) == "gpu");
}

TEST_CASE("backend resolution follows the machine", "[common]") {
  std::ostringstream notice;
  CHECK(resolve_backend(Backend::cpu, notice) == Backend::cpu);
  CHECK(notice.str().empty());
  if (gpu_info().usable) {
    CHECK(resolve_backend(Backend::automatic, notice) == Backend::gpu);
    CHECK(resolve_backend(Backend::gpu, notice) == Backend::gpu);
    CHECK(notice.str().empty());
  } else {
    CHECK(resolve_backend(Backend::automatic, notice) == Backend::cpu);
    const std::string text = notice.str();
    CHECK_THAT(text, rt::testing::starts_with("notice: no usable CUDA device ("));
    CHECK(std::count(text.begin(), text.end(), '\n') == 1);
    CHECK_THROWS_AS(resolve_backend(Backend::gpu, notice), NoGpuError);
    CHECK_FALSE(gpu_info().why_unusable.empty());
  }
  CHECK(cpu_thread_count() >= 1);
}

TEST_CASE("finite_range refuses NaN, infinities and values outside the range", "[common]") {
  auto accepts = [](const std::string& value) {
    CLI::App app{"test", "prog"};
    double x = 0.0;
    app.add_option("--x", x)->check(finite_range(-10.0, 10.0));
    std::vector<std::string> args{"prog", "--x", value};
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    try {
      app.parse(int(argv.size()), argv.data());
    } catch (const CLI::ParseError&) {
      return false;
    }
    return true;
  };
  CHECK(accepts("3.5"));
  CHECK(accepts("-10"));
  CHECK(accepts("10"));
  CHECK_FALSE(accepts("nan"));
  CHECK_FALSE(accepts("inf"));
  CHECK_FALSE(accepts("-inf"));
  CHECK_FALSE(accepts("10.5"));
  CHECK_FALSE(accepts("x"));
}
