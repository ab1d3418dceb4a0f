// The fill and work of an elimination order counted on the graph (elimination_cost) against the
// elimination game played out on a dense pattern (Parter, Rose: eliminating a vertex joins its
// remaining neighbours), on chains, stars and random graphs in random orders.
#include "timestepping/elimination_fill.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>
#include <vector>

namespace latticedyn {
namespace {

struct Graph {
  std::vector<PetscInt> start{0}, columns;
};

Graph from_edges(int n, const std::vector<std::pair<int, int>>& edges, bool with_diagonal) {
  std::vector<std::vector<PetscInt>> rows(n);
  for (auto [a, b] : edges) rows[a].push_back(b), rows[b].push_back(a);
  Graph g;
  for (int i = 0; i < n; ++i) {
    if (with_diagonal) rows[i].push_back(i);
    std::sort(rows[i].begin(), rows[i].end());
    g.columns.insert(g.columns.end(), rows[i].begin(), rows[i].end());
    g.start.push_back(static_cast<PetscInt>(g.columns.size()));
  }
  return g;
}

// The elimination game: the k-th vertex's neighbours not yet eliminated are its column of L.
EliminationCost played_out(int n, const std::vector<std::pair<int, int>>& edges, const std::vector<PetscInt>& order) {
  std::vector<std::vector<char>> adjacent(n, std::vector<char>(n, 0));
  for (auto [a, b] : edges) adjacent[a][b] = adjacent[b][a] = 1;
  std::vector<char> gone(n, 0);
  EliminationCost cost;
  for (PetscInt v : order) {
    std::vector<int> left;
    for (int u = 0; u < n; ++u)
      if (u != v && !gone[u] && adjacent[v][u]) left.push_back(u);
    cost.entries += left.size();
    cost.work += static_cast<double>(left.size()) * left.size();
    for (int a : left)
      for (int b : left)
        if (a != b) adjacent[a][b] = 1;
    gone[v] = 1;
  }
  return cost;
}

std::vector<PetscInt> identity(int n) {
  std::vector<PetscInt> order(n);
  std::iota(order.begin(), order.end(), PetscInt{0});
  return order;
}

TEST(EliminationFill, AChainInItsOwnOrderFillsNothing) {
  const int n = 50;
  std::vector<std::pair<int, int>> edges;
  for (int i = 0; i + 1 < n; ++i) edges.emplace_back(i, i + 1);
  const Graph g = from_edges(n, edges, true);
  const EliminationCost own = elimination_cost(g.start, g.columns, identity(n));
  EXPECT_EQ(own.entries, n - 1);
  EXPECT_EQ(own.work, n - 1);
  // From both ends towards the middle: still no fill. From the middle outwards: every step
  // eliminates a vertex with two remaining neighbours, joined by fill.
  std::vector<PetscInt> middle_first;
  for (int i = n / 2, j = n / 2 - 1; i < n || j >= 0; ++i, --j) {
    if (i < n) middle_first.push_back(i);
    if (j >= 0) middle_first.push_back(j);
  }
  const EliminationCost outwards = elimination_cost(g.start, g.columns, middle_first);
  EXPECT_EQ(outwards.entries, played_out(n, edges, middle_first).entries);
  EXPECT_GT(outwards.entries, n);
}

TEST(EliminationFill, AStarsCentreFirstFillsEverything) {
  const int n = 12;
  std::vector<std::pair<int, int>> edges;
  for (int i = 1; i < n; ++i) edges.emplace_back(0, i);
  const Graph g = from_edges(n, edges, false);
  const EliminationCost centre_first = elimination_cost(g.start, g.columns, identity(n));
  EXPECT_EQ(centre_first.entries, n * (n - 1) / 2);  // L is full
  std::vector<PetscInt> centre_last = identity(n);
  std::rotate(centre_last.begin(), centre_last.begin() + 1, centre_last.end());
  EXPECT_EQ(elimination_cost(g.start, g.columns, centre_last).entries, n - 1);
}

TEST(EliminationFill, MatchesTheEliminationGameOnRandomGraphs) {
  std::mt19937 random(20261207);
  for (int trial = 0; trial < 60; ++trial) {
    const int n = 5 + trial % 30;
    const double density = 0.05 + 0.3 * (trial % 7) / 6.0;
    std::vector<std::pair<int, int>> edges;
    std::uniform_real_distribution<double> draw(0.0, 1.0);
    for (int a = 0; a < n; ++a)
      for (int b = a + 1; b < n; ++b)
        if (draw(random) < density) edges.emplace_back(a, b);
    const Graph g = from_edges(n, edges, trial % 2 == 0);
    std::vector<PetscInt> order = identity(n);
    std::shuffle(order.begin(), order.end(), random);
    const EliminationCost counted = elimination_cost(g.start, g.columns, order);
    const EliminationCost game = played_out(n, edges, order);
    EXPECT_EQ(counted.entries, game.entries) << "trial " << trial;
    EXPECT_EQ(counted.work, game.work) << "trial " << trial;
  }
}

TEST(EliminationFill, RejectsAnOrderThatIsNotAPermutation) {
  const Graph g = from_edges(3, {{0, 1}, {1, 2}}, true);
  const std::vector<PetscInt> twice{0, 1, 1};
  EXPECT_THROW(elimination_cost(g.start, g.columns, twice), std::invalid_argument);
  const std::vector<PetscInt> short_order{0, 1};
  EXPECT_THROW(elimination_cost(g.start, g.columns, short_order), std::invalid_argument);
}

}  // namespace
}  // namespace latticedyn
