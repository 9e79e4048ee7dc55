#include "detector/bayes_filter.h"

#include <gtest/gtest.h>

#include <cmath>

namespace memloop {
namespace {

// A line 1 - 2 - ... - n: every location's neighbourhood within `range`.
Neighbourhoods Line(int n, int range) {
  Neighbourhoods neighbourhoods;
  for (int j = 1; j <= n; ++j) {
    for (int distance = 0; distance <= range; ++distance) {
      for (int i : {j - distance, j + distance}) {
        if (i >= 1 && i <= n && (distance > 0 || i == j)) {
          if (distance == 0 && !neighbourhoods[j].empty()) continue;
          neighbourhoods[j].emplace_back(i, distance);
        }
      }
    }
  }
  return neighbourhoods;
}

Likelihood MakeLikelihood(IdMap<double> values, double virtual_place) {
  Likelihood likelihood;
  likelihood.values = std::move(values);
  likelihood.virtual_place = virtual_place;
  return likelihood;
}

TEST(BayesFilterTest, NeighbourTransitionIsADiscretizedGaussianSummingTo09) {
  BayesFilter filter{FilterOptions()};  // sigma 1.6 links, range 4
  // Centre of a line of five: distances 0, 1, 1, 2, 2. Weights exp(-d^2 / 5.12):
  // 1, 0.8225775, 0.4578334; total 3.5608218; scaled to 0.9.
  const auto column = filter.NeighbourTransition(Line(5, 4).at(3));
  ASSERT_EQ(column.size(), 5u);
  double sum = 0;
  for (const auto& [id, p] : column) {
    sum += p;
    const int distance = std::abs(id - 3);
    const double expected[] = {0.252750639692751, 0.20790700509316629, 0.11571767506045821};
    EXPECT_NEAR(p, expected[distance], 1e-12) << "location " << id;
  }
  EXPECT_NEAR(sum, 0.9, 1e-12);
}

TEST(BayesFilterTest, EveryColumnOfTheTransitionModelSumsToOne) {
  BayesFilter filter{FilterOptions()};
  // A graph with a loop closure: 1-2-3-4-5-6-7-8 plus 8-2, so distances vary per column.
  const std::map<LocationId, std::vector<LocationId>> links = {
      {1, {2}},    {2, {1, 3, 8}}, {3, {2, 4}}, {4, {3, 5}},
      {5, {4, 6}}, {6, {5, 7}},    {7, {6, 8}}, {8, {7, 2}}};
  Neighbourhoods graph;
  for (const auto& entry : links) {
    graph[entry.first] =
        FindNeighbourhood(entry.first, 4, [&](LocationId id) { return links.at(id); });
  }
  for (const auto& [j, neighbourhood] : graph) {
    double column = 1.0 - FilterOptions().virtual_place_stay;  // p(S_t=-1 | S_t-1=j) = 0.1
    for (const auto& entry : filter.NeighbourTransition(neighbourhood)) column += entry.second;
    EXPECT_NEAR(column, 1.0, 1e-12) << "column " << j;
  }
}

TEST(BayesFilterTest, FirstUpdateByHand) {
  BayesFilter filter{FilterOptions()};
  // Prior: p(-1) = 1. Belief: p(i) = 0.1 / 3, p(-1) = 0.9.
  // Unnormalized: 2 * 0.0333, 1 * 0.0333, 1 * 0.0333, 1.5 * 0.9 = 1.35; total 1.4833333.
  filter.Update(MakeLikelihood({{1, 2.0}, {2, 1.0}, {3, 1.0}}, 1.5), Line(3, 4));
  EXPECT_NEAR(filter.posterior().at(1), (0.2 / 3) / 1.4833333333333334, 1e-12);
  EXPECT_NEAR(filter.posterior().at(2), (0.1 / 3) / 1.4833333333333334, 1e-12);
  EXPECT_NEAR(filter.virtual_place(), 1.35 / 1.4833333333333334, 1e-12);
}

// Oracle: the same update as a dense matrix-vector product, built independently.
TEST(BayesFilterTest, MatchesADenseTransitionMatrix) {
  const FilterOptions options;
  const int n = 7;
  const Neighbourhoods neighbourhoods = Line(n, options.neighbour_range);
  BayesFilter filter(options);
  std::vector<double> prior(n + 1, 0.0);  // index 0: the virtual place
  prior[0] = 1.0;
  const std::vector<IdMap<double>> observations = {
      {{1, 1.0}, {2, 1.0}, {3, 3.0}, {4, 1.0}, {5, 1.0}, {6, 1.0}, {7, 1.0}},
      {{1, 1.0}, {2, 1.0}, {3, 1.0}, {4, 2.5}, {5, 1.0}, {6, 1.0}, {7, 1.0}},
      {{1, 1.0}, {2, 1.0}, {3, 1.0}, {4, 1.0}, {5, 4.0}, {6, 1.2}, {7, 1.0}}};
  const std::vector<double> virtual_likelihoods = {1.8, 1.3, 1.1};
  for (size_t step = 0; step < observations.size(); ++step) {
    // T[i][j] = p(S_t = i | S_t-1 = j).
    std::vector<std::vector<double>> transition(n + 1, std::vector<double>(n + 1, 0.0));
    transition[0][0] = 0.9;
    for (int i = 1; i <= n; ++i) transition[i][0] = 0.1 / n;
    for (int j = 1; j <= n; ++j) {
      transition[0][j] = 0.1;
      double total = 0;
      for (int i = std::max(1, j - 4); i <= std::min(n, j + 4); ++i) {
        total += std::exp(-(i - j) * (i - j) / (2 * 1.6 * 1.6));
      }
      for (int i = std::max(1, j - 4); i <= std::min(n, j + 4); ++i) {
        transition[i][j] = 0.9 * std::exp(-(i - j) * (i - j) / (2 * 1.6 * 1.6)) / total;
      }
    }
    std::vector<double> posterior(n + 1, 0.0);
    double eta = 0;
    for (int i = 0; i <= n; ++i) {
      double belief = 0;
      for (int j = 0; j <= n; ++j) belief += transition[i][j] * prior[j];
      posterior[i] = (i == 0 ? virtual_likelihoods[step] : observations[step].at(i)) * belief;
      eta += posterior[i];
    }
    for (double& p : posterior) p /= eta;
    prior = posterior;

    filter.Update(MakeLikelihood(observations[step], virtual_likelihoods[step]), neighbourhoods);
    EXPECT_NEAR(filter.virtual_place(), posterior[0], 1e-12) << "step " << step;
    double total = filter.virtual_place();
    for (int i = 1; i <= n; ++i) {
      EXPECT_NEAR(filter.posterior().at(i), posterior[i], 1e-12) << "step " << step << " i " << i;
      total += filter.posterior().at(i);
    }
    EXPECT_NEAR(total, 1.0, 1e-12);  // normalized
  }
}

TEST(BayesFilterTest, StateSpaceFollowsWorkingMemory) {
  BayesFilter filter{FilterOptions()};
  filter.Update(MakeLikelihood({{1, 3.0}, {2, 1.0}}, 1.0), Line(2, 4));
  filter.Remove(1);  // transferred to LTM
  Neighbourhoods after;
  after[2] = {{2, 0}, {3, 1}};
  after[3] = {{3, 0}, {2, 1}};  // retrieved or new: enters with prior 0
  filter.Update(MakeLikelihood({{2, 1.0}, {3, 1.0}}, 1.0), after);
  EXPECT_EQ(filter.posterior().count(1), 0u);
  EXPECT_GT(filter.posterior().at(3), 0.0);  // reached through the virtual place and from 2
  double total = filter.virtual_place();
  for (const auto& entry : filter.posterior()) total += entry.second;
  EXPECT_NEAR(total, 1.0, 1e-12);
}

}  // namespace
}  // namespace memloop
