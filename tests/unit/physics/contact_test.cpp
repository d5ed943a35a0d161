// The node-level contact law: impenetrability, Coulomb friction, momentum conservation with two
// and three bodies, rigid bodies as infinite mass.
#include "talus/physics/contact.hpp"

#include <gtest/gtest.h>

namespace talus {
namespace {

ContactNode<2> two_bodies(double mu) {
  ContactNode<2> node;
  node.n = 2;
  for (int k = 0; k < 2; ++k) {
    node.body[k] = k;
    node.rigid[k] = false;
    node.surface_normal[k].setZero();
    node.mu[k] = mu;
    node.x[k].setZero();
  }
  // Body 0 above the node, body 1 below: sum m grad N points from a body's particles towards the
  // node, i.e. out of the body.
  node.m[0] = 2.0, node.grad_m[0] = Vec<2>(0.0, -3.0); // body 0 lies above the node
  node.m[1] = 6.0, node.grad_m[1] = Vec<2>(0.0, 5.0);  // body 1 lies below: the master
  node.rank[0] = 2.0, node.rank[1] = 6.0;
  node.v[0] = Vec<2>(1.0, -2.0); // moving down onto body 1 and sliding
  node.v[1] = Vec<2>(0.0, 0.0);
  return node;
}

TEST(Contact, FrictionlessRemovesOnlyTheNormalApproach) {
  ContactNode<2> node = two_bodies(0.0);
  const Vec<2> p0 = node.m[0] * node.v[0] + node.m[1] * node.v[1];
  ASSERT_TRUE(resolve_contact(node, ContactLaw{-1.0, 1.0}));
  EXPECT_DOUBLE_EQ(node.v[0][1], node.v[1][1]); // same normal velocity
  EXPECT_NE(node.v[0][0], node.v[1][0]);        // tangential slip kept
  const Vec<2> p1 = node.m[0] * node.v[0] + node.m[1] * node.v[1];
  EXPECT_LT((p1 - p0).norm(), 1e-14);
  // Centre of mass normal velocity: (2 * -2 + 0) / 8 = -0.5.
  EXPECT_DOUBLE_EQ(node.v[0][1], -0.5);
  EXPECT_DOUBLE_EQ(node.v[0][0], 1.0); // frictionless: tangential velocities untouched
  EXPECT_DOUBLE_EQ(node.v[1][0], 0.0);
}

TEST(Contact, CoulombFrictionLimitsTheTangentialCorrection) {
  // Relative to the centre of mass (0.25, -0.5): body 0 moves (0.75, -1.5). Normal correction
  // 1.5; friction mu * 1.5 = 0.3 removes 0.3 of its 0.75 tangential relative velocity.
  ContactNode<2> node = two_bodies(0.2);
  resolve_contact(node, ContactLaw{-1.0, 1.0});
  EXPECT_NEAR(node.v[0][0], 1.0 - 0.3, 1e-14);
  EXPECT_NEAR(node.v[0][1], -0.5, 1e-14);
  // Body 1 takes the opposite impulse: m0 * 0.3 / m1 = 0.1 along x.
  EXPECT_NEAR(node.v[1][0], 0.1, 1e-14);
  // Enough friction sticks the bodies together.
  ContactNode<2> stick = two_bodies(1.0);
  resolve_contact(stick, ContactLaw{-1.0, 1.0});
  EXPECT_LT((stick.v[0] - stick.v[1]).norm(), 1e-14);
}

TEST(Contact, SeparatingBodiesAreLeftAlone) {
  ContactNode<2> node = two_bodies(0.5);
  node.v[0] = Vec<2>(1.0, 2.0); // moving away from body 1
  EXPECT_FALSE(resolve_contact(node, ContactLaw{-1.0, 1.0}));
  EXPECT_EQ(node.v[0], Vec<2>(1.0, 2.0));
}

// A bonded node holds a separation up to its tensile capacity and is then closed (it measures
// the interface's tangential slip); past it the bond opens (it measures the whole relative
// velocity, opening included).
TEST(Contact, BondIsClosedUntilItsTensileCapacityIsExceeded) {
  ContactNode<2> approach = two_bodies(0.2);
  ASSERT_TRUE(resolve_contact(approach, ContactLaw{-1.0, 1.0}, 1.0));
  EXPECT_TRUE(approach.closed[0] && approach.closed[1]);
  // Body 0 pulls away: relative to the centre of mass it separates at 1.5 along the normal.
  // The tensile capacity as a velocity change is tension * dt / m: 4 / 2 = 2 holds it for body
  // 0 (and 4 / 6 for body 1, which separates at 0.5: held too).
  auto bonded = [](const Vec<2>& v0, double tension) {
    ContactNode<2> n = two_bodies(0.2);
    n.v[0] = v0;
    for (int k = 0; k < 2; ++k)
      n.tension[k] = tension, n.cohesion[k] = 1.0;
    return n;
  };
  ContactNode<2> held = bonded(Vec<2>(1.0, 2.0), 4.0);
  ASSERT_TRUE(resolve_contact(held, ContactLaw{-1.0, 1.0}, 1.0));
  EXPECT_TRUE(held.closed[0] && held.closed[1]);
  EXPECT_FALSE(held.opened[0] || held.opened[1]);
  EXPECT_NEAR(held.v[0][1], held.v[1][1], 1e-14); // the separation is removed
  // 2 / 2 = 1 < 1.5: body 0's bond opens (its tangential 0.75 is still resisted by the cohesive
  // capacity 1 / 2, so it is corrected, but it is not closed); body 1's too (2 / 6 < 0.5).
  ContactNode<2> opened = bonded(Vec<2>(1.0, 2.0), 2.0);
  resolve_contact(opened, ContactLaw{-1.0, 1.0}, 1.0);
  EXPECT_TRUE(opened.opened[0] && opened.opened[1]); // the whole relative velocity is slip
  EXPECT_FALSE(opened.closed[0] || opened.closed[1]);
  EXPECT_GT(opened.v[0][1] - opened.v[1][1], 0.0); // still separating
  // Pulled straight apart past the capacity, nothing is corrected, yet the bond has opened.
  ContactNode<2> pulled = bonded(Vec<2>(0.0, 2.0), 2.0);
  EXPECT_FALSE(resolve_contact(pulled, ContactLaw{-1.0, 1.0}, 1.0));
  EXPECT_TRUE(pulled.opened[0] && pulled.opened[1]);
  EXPECT_FALSE(pulled.closed[0] || pulled.closed[1]);
}

TEST(Contact, GapCheckIgnoresBodiesThatAreStillApart) {
  ContactNode<2> node = two_bodies(0.0);
  node.x[0] = Vec<2>(0.0, 0.5); // mean positions 1.5 cells apart along the normal
  node.x[1] = Vec<2>(0.0, -1.0);
  EXPECT_FALSE(resolve_contact(node, ContactLaw{0.8, 1.0}));
  node.x[0] = Vec<2>(0.0, 0.3); // 0.7 cells: in contact
  node.x[1] = Vec<2>(0.0, -0.4);
  EXPECT_TRUE(resolve_contact(node, ContactLaw{0.8, 1.0}));
}

TEST(Contact, RigidBodyHasInfiniteMass) {
  ContactNode<2> node = two_bodies(0.0);
  node.rigid[1] = true;
  node.v[1] = Vec<2>(0.0, 0.0);
  node.surface_normal[1] = Vec<2>(0.0, 1.0);
  resolve_contact(node, ContactLaw{-1.0, 1.0});
  EXPECT_EQ(node.v[1], Vec<2>(0.0, 0.0));
  EXPECT_DOUBLE_EQ(node.v[0][1], 0.0); // all normal approach removed
  EXPECT_DOUBLE_EQ(node.v[0][0], 1.0);
}

// Three bodies meeting at one node, approaching from three directions with different masses:
// the node's momentum is conserved to round-off and the approach is reduced for every body.
TEST(Contact, ThreeBodiesAtOneNodeConserveMomentum) {
  ContactNode<2> node;
  node.n = 3;
  const Vec<2> dirs[3] = {Vec<2>(1, 0), Vec<2>(-0.5, 0.866), Vec<2>(-0.5, -0.866)};
  const double masses[3] = {1.0, 2.5, 4.0};
  for (int k = 0; k < 3; ++k) {
    node.body[k] = k;
    node.m[k] = masses[k];
    node.rank[k] = masses[k];
    node.grad_m[k] = -masses[k] * dirs[k]; // body k lies in direction dirs[k] from the node
    node.v[k] = -dirs[k] * (1.0 + k);      // each moves towards the node
    node.x[k].setZero();
    node.rigid[k] = false;
    node.surface_normal[k].setZero();
    node.mu[k] = 0.3;
  }
  Vec<2> p0 = Vec<2>::Zero();
  for (int k = 0; k < 3; ++k)
    p0 += node.m[k] * node.v[k];
  double approach_before = 0, approach_after = 0;
  auto approach = [&](const ContactNode<2>& nd) {
    double a = 0;
    for (int i = 0; i < 3; ++i)
      for (int j = i + 1; j < 3; ++j)
        a += std::max(0.0, (nd.v[i] - nd.v[j]).dot(dirs[j] - dirs[i]));
    return a;
  };
  approach_before = approach(node);
  ASSERT_TRUE(resolve_contact(node, ContactLaw{-1.0, 1.0}));
  approach_after = approach(node);
  Vec<2> p1 = Vec<2>::Zero();
  for (int k = 0; k < 3; ++k)
    p1 += node.m[k] * node.v[k];
  EXPECT_LT((p1 - p0).norm(), 1e-13);
  EXPECT_LT(approach_after, 0.05 * approach_before);
}

// A pair of a node that three or more bodies share (`symmetric`): the normal is the difference of
// the two mass gradients, so a corner of the master (a gradient pointing diagonally out of it)
// does not tilt it, and it stays opposite for the two bodies.
TEST(Contact, SymmetricPairTakesTheDifferenceOfTheGradients) {
  ContactNode<2> node = two_bodies(0.0);
  node.rank[0] = 10.0, node.rank[1] = 1.0; // body 0 the master
  node.grad_m[0] = Vec<2>(1.0, -1.0);      // the master's corner: out of it along +x and -y
  node.grad_m[1] = Vec<2>(-1.0, -1.0);     // the other's corner, mirrored
  EXPECT_TRUE(contact_direction(node, 1).isApprox(Vec<2>(-1.0, 1.0))); // the master's, reversed
  node.symmetric = true;
  EXPECT_TRUE(contact_direction(node, 0).isApprox(Vec<2>(2.0, 0.0)));
  EXPECT_TRUE(contact_direction(node, 1).isApprox(Vec<2>(-2.0, 0.0)));
}

} // namespace
} // namespace talus
