// What both solvers share (radiosity/solver_frame.hpp): the link and memory
// budget, the iteration loop and its interrupt checks, and the statistics
// every run writes to stats.json.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include <nlohmann/json.hpp>

#include "radiosity/solver_frame.hpp"

namespace lhr {
namespace {

TEST(LinkBudget, WithoutLimitsItNeverRefuses) {
  LinkBudget budget(0, 0);
  SolverStats stats;
  EXPECT_FALSE(budget.counts_bytes());
  budget.plan(1'000'000, 1'000'000'000);
  EXPECT_FALSE(budget.refuses(1'000'000'000, 1'000'000, stats));
  EXPECT_FALSE(stats.link_budget_reached);
  EXPECT_FALSE(stats.memory_budget_reached);
}

TEST(LinkBudget, MaxLinksIsTheCapAndItsRefusalIsReportedAsSuch) {
  LinkBudget budget(100, 0);
  SolverStats stats;
  EXPECT_EQ(budget.cap(), 100u);
  EXPECT_FALSE(budget.refuses(97, 3, stats));
  EXPECT_FALSE(stats.link_budget_reached);
  EXPECT_TRUE(budget.refuses(98, 3, stats));
  EXPECT_TRUE(stats.link_budget_reached);
  EXPECT_FALSE(stats.memory_budget_reached);
}

TEST(LinkBudget, TheMemoryCapLeavesATenthOfTheBudgetAtTheBytesPerLinkSoFar) {
  // 10 links in 500 bytes: 50 bytes a link. 90 % of 1000 bytes leaves room
  // for (900 − 500) / 50 = 8 more.
  LinkBudget budget(0, 1000);
  SolverStats stats;
  EXPECT_TRUE(budget.counts_bytes());
  budget.plan(10, 500);
  EXPECT_EQ(budget.cap(), 18u);
  EXPECT_FALSE(budget.refuses(10, 8, stats));
  EXPECT_TRUE(budget.refuses(10, 9, stats));
  EXPECT_TRUE(stats.memory_budget_reached);
  EXPECT_FALSE(stats.link_budget_reached);
}

TEST(LinkBudget, TheNearerOfTheTwoCapsHolds) {
  SolverStats stats;
  LinkBudget links_nearer(12, 1000);
  links_nearer.plan(10, 500);
  EXPECT_EQ(links_nearer.cap(), 12u);
  EXPECT_TRUE(links_nearer.refuses(12, 1, stats));
  EXPECT_TRUE(stats.link_budget_reached);
  EXPECT_FALSE(stats.memory_budget_reached);
  // Data already past 90 % of the budget: no room at all, whatever max_links says.
  LinkBudget memory_nearer(1000, 1000);
  memory_nearer.plan(10, 950);
  EXPECT_EQ(memory_nearer.cap(), 10u);
  // A new plan starts from max_links again once the data per link allows it.
  memory_nearer.plan(10, 100);
  EXPECT_EQ(memory_nearer.cap(), 10u + (900u - 100u) / 10u);
}

TEST(IterateUntilConverged, StopsAtTheFirstIterationThatChangesNothingBelowTheTolerance) {
  SolverStats stats;
  std::vector<int> seen;
  std::vector<std::pair<int, double>> reported;
  const auto step = [&](int it, bool last) {
    seen.push_back(it);
    EXPECT_FALSE(last);
    // Refines in iterations 1 and 2; the change falls by ten each time.
    return IterationOutcome{it <= 2, 1.0 / std::pow(10.0, it)};
  };
  iterate_until_converged(
      10, 2e-3, {}, step, [&](int it, double change) { reported.emplace_back(it, change); }, stats);
  // Iteration 3 refines nothing and changes by 1e-3, under the tolerance.
  ASSERT_EQ(seen, (std::vector<int>{1, 2, 3}));
  EXPECT_EQ(stats.iterations, 3);
  EXPECT_DOUBLE_EQ(stats.final_change, 1e-3);
  ASSERT_EQ(reported.size(), 3u);
  EXPECT_EQ(reported.back().first, 3);
}

TEST(IterateUntilConverged, AChangeAboveTheToleranceKeepsItGoingAndTheLastIterationIsMarked) {
  SolverStats stats;
  int calls = 0;
  bool last_seen = false;
  iterate_until_converged(
      4, 1e-6, {},
      [&](int it, bool last) {
        ++calls;
        last_seen = last;
        EXPECT_EQ(last, it == 4);
        return IterationOutcome{false, 0.5};
      },
      {}, stats);
  EXPECT_EQ(calls, 4);
  EXPECT_TRUE(last_seen);
  EXPECT_EQ(stats.iterations, 4);
  EXPECT_DOUBLE_EQ(stats.final_change, 0.5);
}

TEST(IterateUntilConverged, TheCheckpointRunsBeforeEachIterationAndWhatItThrowsStopsTheLoop) {
  SolverStats stats;
  int checkpoints = 0, steps = 0;
  const auto checkpoint = [&] {
    if (++checkpoints == 3) throw std::runtime_error("interrupted");
  };
  EXPECT_THROW(iterate_until_converged(
                   10, 1e-6, checkpoint, [&](int, bool) { ++steps; return IterationOutcome{true, 1.0}; }, {}, stats),
               std::runtime_error);
  EXPECT_EQ(checkpoints, 3);
  EXPECT_EQ(steps, 2);
  EXPECT_EQ(stats.iterations, 2);
}

TEST(SolverStats, WritesTheSizesBytesAndSecondsEveryMethodReports) {
  SolverStats stats;
  stats.links = 7;
  stats.leaves = 5;
  stats.nodes = 9;
  stats.iterations = 3;
  stats.memory_budget_reached = true;
  stats.shadow_rays = 11;
  stats.final_change = 0.25;
  stats.bytes_geometry = 1;
  stats.bytes_hierarchy = 2;
  stats.bytes_values = 3;
  stats.bytes_links = 4;
  stats.seconds_gather = 1.5;
  nlohmann::json doc;
  stats.write_json(doc, "element_values", 42);
  EXPECT_EQ(doc["elements"], 5);
  EXPECT_EQ(doc["links"], 7);
  EXPECT_EQ(doc["nodes"], 9);
  EXPECT_EQ(doc["iterations"], 3);
  EXPECT_EQ(doc["memory_budget_reached"], true);
  EXPECT_EQ(doc["link_budget_reached"], false);
  EXPECT_EQ(doc["shadow_rays"], 11);
  EXPECT_EQ(doc["final_change"], 0.25);
  EXPECT_EQ(doc["bytes"]["element_values"], 3);
  EXPECT_EQ(doc["bytes"]["links"], 4);
  EXPECT_EQ(doc["bytes"]["total"], 42);
  EXPECT_EQ(doc["seconds"]["gather"], 1.5);
  EXPECT_TRUE(doc["seconds"].contains("coefficients"));
  EXPECT_TRUE(doc["seconds"].contains("push_pull"));
}

TEST(PhaseTimer, AddsItsScopeOnceAndStopEndsItEarly) {
  double seconds = 1.0;
  {
    PhaseTimer timer(seconds);
    timer.stop();
    const double after_stop = seconds;
    EXPECT_GE(after_stop, 1.0);
    timer.stop();
    EXPECT_EQ(seconds, after_stop);
  }
  const double after_scope = seconds;
  { PhaseTimer timer(seconds); }
  EXPECT_GE(seconds, after_scope);
}

}  // namespace
}  // namespace lhr
