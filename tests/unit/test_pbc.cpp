// Unit tests of the averaged periodic boundary algebra (ncf_pbc.h).

#include "ncf_input_error.h"
#include "ncf_pbc.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>

using namespace NCF;

namespace {
std::vector<FaceNode> random_nodes(int n, double lu, double lv, unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, lu), v(0.0, lv);
  std::vector<FaceNode> nodes;
  for (int side : {-1, 1})
    for (int i = 0; i < n; i++) nodes.push_back({side, u(rng), v(rng)});
  return nodes;
}
}    // namespace

TEST(PbcMesh, AboutOneNodePerCell)
{
  for (int n : {10, 57, 400}) {
    auto nodes = random_nodes(n, 5e-3, 4e-4, n);
    auto m = auto_face_mesh(nodes, 5e-3);
    const double cells = m.nu * m.nv;
    EXPECT_GT(cells, 0.6 * n) << n;
    EXPECT_LT(cells, 1.6 * n) << n;
    // cells roughly square
    const double hu = m.lu / m.nu, hv = (m.vhi - m.vlo) / m.nv;
    if (m.nu > 1 && m.nv > 1) EXPECT_LT(std::max(hu / hv, hv / hu), 2.5) << n;
  }
}

TEST(PbcMesh, LatticeOfEndPointsGivesOneCellPerPoint)
{
  // sigma = 0 mat: 12 columns x 3 rows of chain ends, the same on both faces
  std::vector<FaceNode> nodes;
  const double lu = 2.4e-3;
  for (int side : {-1, 1})
    for (int r = 0; r < 3; r++)
      for (int c = 0; c < 12; c++) nodes.push_back({side, (c + 0.25) * lu / 12, 1e-4 + r * 7e-5});
  auto m = auto_face_mesh(nodes, lu);
  EXPECT_EQ(m.nu, 12);
  EXPECT_EQ(m.nv, 3);
  int ng = 0;
  auto g = face_groups(m, nodes, ng);
  EXPECT_EQ(ng, 36);
  // each group: exactly the lower node and its periodic image
  for (int k = 0; k < 36; k++) EXPECT_EQ(g[k], g[36 + k]);
  std::vector<int> sorted(g.begin(), g.begin() + 36);
  std::sort(sorted.begin(), sorted.end());
  EXPECT_EQ(std::unique(sorted.begin(), sorted.end()) - sorted.begin(), 36);
}

TEST(PbcGroups, EveryGroupHasBothFacesAndEveryNodeAGroup)
{
  for (unsigned seed = 1; seed <= 20; seed++) {
    auto nodes = random_nodes(40, 3e-3, 3e-4, seed);
    auto m = auto_face_mesh(nodes, 3e-3);
    int ng = 0;
    auto g = face_groups(m, nodes, ng);
    ASSERT_GT(ng, 0);
    std::vector<int> low(ng, 0), up(ng, 0);
    for (std::size_t i = 0; i < nodes.size(); i++) {
      ASSERT_GE(g[i], 0);
      ASSERT_LT(g[i], ng);
      (nodes[i].side < 0 ? low : up)[g[i]]++;
    }
    for (int k = 0; k < ng; k++) {
      EXPECT_GT(low[k], 0) << "seed " << seed << " group " << k;
      EXPECT_GT(up[k], 0) << "seed " << seed << " group " << k;
    }
    // the same nodes in another order give the same partition
    std::vector<int> perm(nodes.size());
    for (std::size_t i = 0; i < perm.size(); i++) perm[i] = (int) i;
    std::shuffle(perm.begin(), perm.end(), std::mt19937(seed));
    std::vector<FaceNode> shuffled;
    for (int p : perm) shuffled.push_back(nodes[p]);
    int ng2 = 0;
    auto g2 = face_groups(m, shuffled, ng2);
    EXPECT_EQ(ng, ng2);
    std::map<int, int> relabel;
    for (std::size_t k = 0; k < perm.size(); k++) {
      auto it = relabel.emplace(g2[k], g[perm[k]]).first;
      EXPECT_EQ(it->second, g[perm[k]]) << "partition differs, seed " << seed;
    }
  }
}

TEST(PbcGroups, MergingWorksAcrossThePeriodicSeam)
{
  // one lower node just after u = 0, one upper node just before u = lu: on a 10-cell row they are
  // 2 % of the period apart through the seam, 96 % apart the other way
  const double lu = 1.0;
  std::vector<FaceNode> nodes = {{-1, 0.01, 0.0}, {1, 0.99, 0.0}, {-1, 0.45, 0.0}, {1, 0.55, 0.0}};
  FaceMesh m;
  m.lu = lu;
  m.nu = 10;
  m.nv = 1;
  m.vlo = -1;
  m.vhi = 1;
  int ng = 0;
  auto g = face_groups(m, nodes, ng);
  EXPECT_EQ(ng, 2);
  EXPECT_EQ(g[0], g[1]);
  EXPECT_EQ(g[2], g[3]);
  EXPECT_NE(g[0], g[2]);
}

TEST(PbcGroups, OneFaceWithoutNodesIsAnError)
{
  std::vector<FaceNode> nodes = {{-1, 0.1, 0.0}, {-1, 0.2, 0.0}};
  auto m = auto_face_mesh(nodes, 1.0);
  int ng = 0;
  EXPECT_THROW(face_groups(m, nodes, ng), InputError);
}

TEST(PbcWeights, SumToZeroPerGroupAndAverageEachFace)
{
  auto nodes = random_nodes(30, 2e-3, 2e-4, 99);
  auto m = auto_face_mesh(nodes, 2e-3);
  int ng = 0;
  auto g = face_groups(m, nodes, ng);
  auto w = face_weights(nodes, g, ng);
  std::vector<double> sum(ng, 0.0), plus(ng, 0.0);
  for (std::size_t i = 0; i < nodes.size(); i++) {
    sum[g[i]] += w[i];
    if (w[i] > 0) plus[g[i]] += w[i];
  }
  for (int k = 0; k < ng; k++) {
    EXPECT_NEAR(sum[k], 0.0, 1e-15);
    EXPECT_NEAR(plus[k], 1.0, 1e-15);    // the upper reference point is the mean of its nodes
  }
}

TEST(PbcMultiplier, MakesTheConstraintExactAndConservesMomentum)
{
  // one group: 3 upper nodes, 2 lower nodes, arbitrary masses and predicted positions
  std::vector<double> w = {1.0 / 3, 1.0 / 3, 1.0 / 3, -0.5, -0.5};
  std::vector<double> m = {1e-9, 2e-9, 0.5e-9, 3e-9, 1.5e-9};
  std::vector<double> x = {4.01e-3, 3.98e-3, 4.005e-3, 1e-5, -2e-5};
  const double target = 4.0e-3, dt = 2e-9;
  double r = -target, s = 0.0;
  for (int i = 0; i < 5; i++) {
    r += w[i] * x[i];
    s += w[i] * w[i] / m[i];
  }
  const double lambda = constraint_multiplier(r, dt * dt * s);
  double c = -target, fsum = 0.0;
  for (int i = 0; i < 5; i++) {
    const double f = w[i] * lambda;
    fsum += f;
    c += w[i] * (x[i] + dt * dt * f / m[i]);
  }
  EXPECT_NEAR(c, 0.0, 1e-18);
  EXPECT_NEAR(fsum, 0.0, 1e-12 * std::fabs(lambda));
}

// face-normal hold on the x faces of a box tilted by xy: every node's n . x = b_i (n = (1, a))
// and the group's constraint along y both exact after the step, whatever the tilt; the forces
// of a group's in-face constraint still sum to zero
TEST(PbcHeldMultiplier, MakesNodeHoldsAndGroupConstraintExactTogether)
{
  const std::vector<double> w = {1.0 / 3, 1.0 / 3, 1.0 / 3, -0.5, -0.5};
  const std::vector<double> m = {1e-9, 2e-9, 0.5e-9, 3e-9, 1.5e-9};
  const std::vector<double> px = {4.01e-3, 3.98e-3, 4.005e-3, 1e-5, -2e-5};    // predicted x
  const std::vector<double> py = {1.1e-3, 0.9e-3, 1.3e-3, 0.2e-3, 2.1e-3};     // predicted y
  const std::vector<double> b = {4.0e-3, 3.99e-3, 4.0e-3, 0.0, 0.0};           // node targets
  const double target_y = 0.1e-3, dt = 2e-9;
  for (double a : {0.0, -0.3, 0.7}) {
    std::vector<double> r(5);
    double R = -target_y, swr = 0.0, s = 0.0;
    for (int i = 0; i < 5; i++) {
      r[i] = px[i] + a * py[i] - b[i];
      R += w[i] * py[i];
      swr += w[i] * r[i];
      s += w[i] * w[i] / m[i];
    }
    const double mu = held_group_multiplier(R, swr, a, dt * dt * s);
    double cy = -target_y, fy_group = 0.0;
    for (int i = 0; i < 5; i++) {
      const double lam = held_node_multiplier(r[i], w[i], mu, a, m[i] / (dt * dt));
      const double fx = lam, fy = lam * a + w[i] * mu;
      const double x1 = px[i] + dt * dt * fx / m[i], y1 = py[i] + dt * dt * fy / m[i];
      EXPECT_NEAR(x1 + a * y1 - b[i], 0.0, 1e-17) << "a = " << a << ", node " << i;
      cy += w[i] * y1;
      fy_group += w[i] * mu;
    }
    EXPECT_NEAR(cy, 0.0, 1e-17) << "a = " << a;
    EXPECT_NEAR(fy_group, 0.0, 1e-12 * std::fabs(mu)) << "a = " << a;
  }
}
