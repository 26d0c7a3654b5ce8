// The report: an aligned table with every row, and JSON with the same rows.
#include <sstream>
#include <thread>

#include "rt_catch.h"
#include <nlohmann/json.hpp>

#include "rt/error.h"
#include "rt/report.h"
#include "rt/timer.h"

using namespace rt;

namespace {

Report sample_report() {
  Report report("Demo", "Mrays/s", "float64 reference");
  report.add_context("device", "test");
  report.add_row({"stable quadratic", "gpu", 0.41, 5060, "0 px differ", {{"pixels", 0}}});
  report.add_row(
      {"textbook quadratic", "cpu", 12.5, 3.25, "1 812 px differ", {{"pixels", 1812}}});
  return report;
}

} // namespace

TEST_CASE("report prints an aligned table", "[common]") {
  std::ostringstream out;
  sample_report().print(out);
  const std::string text = out.str();
  CHECK_THAT(text, rt::testing::contains("variant             backend  ms/frame  Mrays/s  "
                                         "error vs float64 reference"));
  CHECK_THAT(text, rt::testing::contains(
                       "stable quadratic    gpu         0.410    5 060  0 px differ"));
  CHECK_THAT(text,
             rt::testing::contains("textbook quadratic  cpu          12.5     3.25  1 812 px"));
  CHECK_THAT(text, rt::testing::contains("device: test"));
}

TEST_CASE("report JSON carries the same rows", "[common]") {
  const auto json = nlohmann::json::parse(sample_report().to_json());
  CHECK(json["throughput_unit"] == "Mrays/s");
  REQUIRE(json["rows"].size() == 2);
  CHECK(json["rows"][1]["variant"] == "textbook quadratic");
  CHECK(json["rows"][1]["ms_per_frame"] == 12.5);
  CHECK(json["rows"][1]["metrics"]["pixels"] == 1812);
  CHECK(json["context"]["device"] == "test");
  CHECK_THROWS_AS(sample_report().write_json("/nonexistent-dir/r.json"), OutputError);
}

TEST_CASE("digits are grouped by thousands", "[common]") {
  CHECK(group_digits(0) == "0");
  CHECK(group_digits(999) == "999");
  CHECK(group_digits(1000) == "1 000");
  CHECK(group_digits(1234567) == "1 234 567");
  CHECK(group_digits(-45000) == "-45 000");
}

TEST_CASE("timing summary takes the median", "[common]") {
  CHECK(summarize({5, 1, 3}).median_ms == 3);
  CHECK(summarize({4, 1, 3, 2}).median_ms == 2.5);
  CHECK(summarize({4, 1, 3, 2}).min_ms == 1);
  CHECK(summarize({4, 1, 3, 2}).max_ms == 4);
  CHECK_THROWS(summarize({}));
  CHECK(timing_plan(Backend::gpu).warmups >= 5);
  CHECK(timing_plan(Backend::gpu).runs >= 50);
  CHECK(timing_plan(Backend::cpu).runs >= 5);
  CHECK(timing_plan(Backend::cpu, 7).runs == 7);
  int calls = 0;
  const Timing t = time_cpu([&] { ++calls; }, {2, 9});
  CHECK(calls == 11);
  CHECK(t.runs == 9);
}

TEST_CASE("the backend clock measures from one mark to another on the CPU", "[common]") {
  using namespace std::chrono_literals;
  BackendClock clock(Backend::cpu, 3);
  clock.mark(0);
  std::this_thread::sleep_for(2ms); // the steady clock moves at least this far
  clock.mark(1);
  clock.mark(2);
  CHECK(clock.milliseconds_between(0, 1) >= 2.0);
  CHECK(clock.milliseconds_between(1, 1) == 0.0);
  CHECK(clock.milliseconds_between(0, 2) >= clock.milliseconds_between(0, 1));
  CHECK(clock.milliseconds_between(1, 0) <= -2.0);
  CHECK_THROWS_AS(clock.mark(3), std::out_of_range);
  CHECK_THROWS_AS(BackendClock(Backend::automatic, 2), Error);

  BackendStopwatch stopwatch(Backend::cpu);
  std::this_thread::sleep_for(2ms);
  const double first = stopwatch.milliseconds();
  CHECK(first >= 2.0);
  CHECK(stopwatch.milliseconds() >= first); // every reading is from the start
}
