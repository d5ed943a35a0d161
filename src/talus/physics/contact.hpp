// Multi-velocity-field contact at one node (paper section 2.3): each body at the node is compared
// with the centre of mass of all bodies there and the node's total momentum is conserved to
// round-off (a rigid body's velocity is the reference where one is present). The solver gives it
// three or more bodies only where a rigid body is among them or contact.node_law =
// "centre_of_mass" (the paper's law); three or more deformable bodies are otherwise resolved pair
// by pair (Simulation::apply_contact). A pure function of the node's data, tested on its own.
#pragma once

#include "talus/core/math.hpp"

#include <cmath>

namespace talus {

constexpr int max_bodies_at_node = 8;

// The bodies present at one node (mass > 0), with the quantities the law needs.
template <int D>
struct ContactNode {
  int n = 0;
  int body[max_bodies_at_node]{};
  double m[max_bodies_at_node]{};
  Vec<D> v[max_bodies_at_node];      // velocity, corrected in place
  Vec<D> grad_m[max_bodies_at_node]; // sum m_p grad N_I(x_p): points out of the body
  Vec<D> x[max_bodies_at_node];      // mass-weighted nodal position (gap check)
  bool rigid[max_bodies_at_node]{};
  // A body's outward surface normal from its geometry, if it has one (rigid bodies, and bodies
  // with geometric_normal = true); zero: use the mass gradient.
  Vec<D> surface_normal[max_bodies_at_node];
  double mu[max_bodies_at_node]{};   // friction of each body against the others
  double rank[max_bodies_at_node]{}; // master-body order: the larger rank gives the normal
  // Two deformable bodies resolved as one pair of a node three or more share: the normal is
  // grad m_k - grad m_j, the two gradients alike (a corner of the master does not tilt it).
  bool symmetric = false;
  // Cohesive interface seen by each body against the others (paper section 2.4, eq. 37): the
  // cohesive capacity sum N c^p A^p (N) and the tensile capacity (N) of the interface particles
  // at the node; zero where the pair is purely frictional. The interface's friction is in mu.
  double cohesion[max_bodies_at_node]{};
  double tension[max_bodies_at_node]{};
  // Outputs: outward normal used, and the tangential impulse split into its frictional and
  // cohesive parts and the normal impulse (N s) applied to each body.
  Vec<D> normal[max_bodies_at_node];
  double friction_impulse[max_bodies_at_node]{};
  double cohesion_impulse[max_bodies_at_node]{};
  double normal_impulse[max_bodies_at_node]{};
  // Whether the body is held against the others here (corrected, and not a bond opened past its
  // tensile capacity), and whether it is a bond opened past its tensile capacity (corrected or
  // not). These nodes, and only these, measure an interface's slip.
  bool closed[max_bodies_at_node]{};
  bool opened[max_bodies_at_node]{};
};

// Settings of the contact law.
struct ContactLaw {
  // Gap check (Nairn 2013's position check): a body is in contact only if the mean nodal position
  // of the others lies within gap_cutoff gap units of its own along the normal. Two bodies
  // touching across a node, sampled with 2 particles per cell, sit 0.75 cells apart with linear
  // and GIMP weights; a negative cutoff switches the check off (contact on approach alone,
  // eq. 29). The unit is the cell for those and 9/8 of it for the quadratic B-spline, whose
  // wider weights put the two bodies' mean positions 27/32 of a cell apart there.
  double gap_cutoff = 0.8;
  double gap_unit = 1.0;
};

// The contact normal at the node, outward from body k, unnormalised (zero: none). A rigid body's
// exact geometric normal if known. Two bodies: the mass gradient of the master body (the larger
// rank, i.e. the body with more total mass, as Huang et al. 2011's master-slave choice), which
// keeps the normals collinear and is not fooled by the corners of the smaller body; a pair of a
// node three or more bodies share (`symmetric`), own gradient minus the other's. Three or more
// in one law (contact.node_law = "centre_of_mass"): own gradient minus the others'. `rigid`: the
// heaviest rigid body here (-1: none); G: the sum of the bodies' mass gradients.
template <int D>
Vec<D> contact_direction(const ContactNode<D>& node, int k, int rigid, const Vec<D>& G) {
  const int n = node.n;
  const int master = rigid >= 0 ? rigid : (n == 2 ? (node.rank[0] > node.rank[1] ? 0 : 1) : -1);
  if (master >= 0 && !node.surface_normal[master].isZero())
    return master == k ? node.surface_normal[k] : Vec<D>(-node.surface_normal[master]);
  if (n == 2) {
    const int j = 1 - k;
    if (node.symmetric) return node.grad_m[k] - node.grad_m[j];
    const bool own = rigid < 0 ? node.rank[k] > node.rank[j] : false;
    return own ? node.grad_m[k] : Vec<D>(-node.grad_m[j]);
  }
  return 2.0 * node.grad_m[k] - G;
}

// The same, finding the heaviest rigid body and the gradients' sum itself.
template <int D>
Vec<D> contact_direction(const ContactNode<D>& node, int k) {
  int rigid = -1;
  Vec<D> G = Vec<D>::Zero();
  for (int j = 0; j < node.n; ++j) {
    G += node.grad_m[j];
    if (node.rigid[j] && (rigid < 0 || node.m[j] > node.m[rigid])) rigid = j;
  }
  return contact_direction(node, k, rigid, G);
}

// Resolves contact at a node: impenetrability (eq. 32-34) and Coulomb friction (eq. 35-36)
// against the centre-of-mass velocity (normals: see below). Rigid bodies have infinite mass: the
// centre-of-mass velocity is theirs and they are never corrected. Returns true if any body was
// corrected; node.v holds the corrected velocities.
template <int D>
bool resolve_contact(ContactNode<D>& node, const ContactLaw& law, double dt = 0.0) {
  const int n = node.n;
  if (n < 2) return false;
  double M = 0.0;
  Vec<D> P = Vec<D>::Zero(), G = Vec<D>::Zero(), MX = Vec<D>::Zero();
  int rigid = -1;
  for (int k = 0; k < n; ++k) {
    M += node.m[k];
    P += node.m[k] * node.v[k];
    G += node.grad_m[k];
    MX += node.m[k] * node.x[k];
    if (node.rigid[k] && (rigid < 0 || node.m[k] > node.m[rigid])) rigid = k;
  }
  const Vec<D> v_cm = rigid >= 0 ? node.v[rigid] : Vec<D>(P / M);
  Vec<D> c[max_bodies_at_node];
  double m_corrected = 0.0;
  Vec<D> residual = Vec<D>::Zero();
  bool any = false;
  for (int k = 0; k < n; ++k) {
    c[k].setZero();
    node.normal[k].setZero();
    node.friction_impulse[k] = node.cohesion_impulse[k] = node.normal_impulse[k] = 0.0;
    node.closed[k] = node.opened[k] = false;
    if (node.rigid[k]) continue;
    const Vec<D> g = contact_direction(node, k, rigid, G);
    const double g_norm = g.norm();
    if (g_norm <= 0.0) continue;
    const Vec<D> normal = g / g_norm;
    node.normal[k] = normal;
    const Vec<D> dv = node.v[k] - v_cm;
    const double dn = dv.dot(normal);
    // A bonded interface (cohesion or tensile capacity left) holds on approach and separation
    // alike; otherwise only approaching bodies are in contact (eq. 29), and the gap check keeps
    // bodies that are still apart out of it.
    const double cohesion_dv = node.cohesion[k] * dt / node.m[k]; // capacity as a velocity change
    const double tension_dv = node.tension[k] * dt / node.m[k];
    const bool bonded = cohesion_dv > 0.0 || tension_dv > 0.0;
    if (!bonded) {
      if (dn <= 0.0) continue;
      if (law.gap_cutoff >= 0.0) {
        const double m_other = M - node.m[k];
        const Vec<D> x_other = (MX - node.m[k] * node.x[k]) / m_other;
        if ((x_other - node.x[k]).dot(normal) > law.gap_cutoff * law.gap_unit) continue;
      }
    }
    // Normal: remove the approach; a bond also removes a separation up to its tensile capacity.
    const double dn_corr = dn > 0.0 ? dn : (-dn <= tension_dv ? dn : 0.0);
    node.opened[k] = bonded && dn < 0.0 && dn_corr == 0.0;
    const Vec<D> dv_t = dv - dn * normal;
    const double t = dv_t.norm();
    // Tangential: friction mu * (normal approach) plus the cohesive capacity (eq. 35-37); stick
    // if that stops the slip, else slide with the full resistance. An interface's pore pressure
    // has already pushed the bodies apart (the contact pass, push_pore), so the approach is
    // the effective normal force's: mu (sigma_n - p) A.
    // mu is inf where contacts are held while settling: it sticks, and adds nothing at rest.
    const double approach = std::max(dn, 0.0);
    const double friction_dv =
        approach > 0.0 || std::isfinite(node.mu[k]) ? node.mu[k] * approach : 0.0;
    const double resist = friction_dv + cohesion_dv;
    const double t_corr = resist >= t ? t : resist;
    c[k] = dn_corr * normal + (t > 0.0 ? Vec<D>((t_corr / t) * dv_t) : Vec<D>::Zero());
    if (c[k].isZero()) continue;
    node.closed[k] = !node.opened[k];
    node.normal_impulse[k] = node.m[k] * std::max(dn_corr, 0.0);
    node.friction_impulse[k] = node.m[k] * std::min(t_corr, friction_dv);
    node.cohesion_impulse[k] = node.m[k] * (t_corr - std::min(t_corr, friction_dv));
    m_corrected += node.m[k];
    residual += node.m[k] * c[k];
    any = true;
  }
  if (!any) return false;
  // Without a rigid body the corrections must not change the node's momentum. For two bodies
  // the residual is zero by construction; for more it is shared by the corrected bodies.
  for (int k = 0; k < n; ++k) {
    if (c[k].isZero()) continue;
    node.v[k] -= c[k];
    if (rigid < 0) node.v[k] += residual / m_corrected;
  }
  return true;
}

} // namespace talus
