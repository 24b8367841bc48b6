// The finite-element body: explicit update, force assembly, topology operations and restart state.
#include "fem/body.h"

#include "materials/material_table.h"
#include "materials/plasticity.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>

namespace fracdem
{

void Body::build(Mesh mesh, const Material& material, bool rigid)
{
  mesh_ = std::move(mesh);
  material_ = material;
  rigid_ = rigid;
  space_.build(mesh_, material_);
  const int nn = mesh_.num_nodes();
  resize_nodes(nn);
  x_ = mesh_.X;
  std::fill(parent_.begin(), parent_.end(), -1);
  derive_masses();
  state_.assign(space_.state_size(), 0.0);
  stars_.build(mesh_);
  elem_begin_ = 0;
  elem_end_ = mesh_elems_ = mesh_.num_elems();
  elem_parent_.clear();
  cut_nodes_.clear();
  mesh_measure_.clear();
  set_bulk_viscosity(viscosity_); // sizes its accounts for this mesh
}

void Body::resize_nodes(int nn)
{
  x_.resize(3 * nn, 0.0);
  v_.resize(3 * nn, 0.0);
  f_.resize(3 * nn, 0.0);
  f_contact_.resize(3 * nn, 0.0);
  f_contact_prev_.resize(3 * nn, 0.0);
  f_pending_.resize(3 * nn, 0.0);
  v_prescribed_.resize(3 * nn, 0.0);
  bc_.resize(nn, NodeBc::Free);
  held_.resize(nn, 0);
  ramp_.resize(nn, 0.0);
  bc_group_.resize(nn, -1);
  component_group_.resize(3 * static_cast<std::size_t>(nn), -1);
  parent_.resize(nn, -1);
  mass_.resize(nn, 0.0);
  inv_mass_.resize(nn, 0.0);
  if (!counted_.empty()) counted_.resize(nn, 1);
  if (!shared_.empty()) shared_.resize(nn, 0);
  if (!taken_.empty()) taken_.resize(nn, 0.0);
}

void Body::derive_masses()
{
  space_.lumped_masses(mesh_, mass_);
  inv_mass_.resize(mass_.size());
  for (size_t i = 0; i < mass_.size(); ++i)
    inv_mass_[i] = mass_[i] > 0 ? 1.0 / mass_[i] : 0.0;
}

void Body::set_bulk_viscosity(const BulkViscosity& bv)
{
  viscosity_ = bv;
  const std::size_t ne = viscosity_.on ? mesh_.num_elems() : 0;
  for (std::vector<double>* a :
       {&viscous_work_, &viscous_force_prev_, &viscous_force_, &viscous_rate_})
    a->assign(ne, 0.0);
}

void Body::set_masses(const std::vector<double>& mass)
{
  if (mass.size() != mass_.size())
    throw FeError(-1, "Body::set_masses: one mass per node expected");
  mass_ = mass;
  for (size_t n = 0; n < mass_.size(); ++n)
    inv_mass_[n] = mass_[n] > 0 ? 1.0 / mass_[n] : 0.0;
}

void Body::set_counted_nodes(std::vector<std::uint8_t> counted)
{
  if (!counted.empty() && static_cast<int>(counted.size()) != num_nodes())
    throw FeError(-1, "Body::set_counted_nodes: one flag per node expected");
  counted_ = std::move(counted);
}

void Body::set_shared_nodes(std::vector<std::uint8_t> shared)
{
  if (!shared.empty() && static_cast<int>(shared.size()) != num_nodes())
    throw FeError(-1, "Body::set_shared_nodes: one flag per node expected");
  shared_ = std::move(shared);
  taken_.assign(shared_.empty() ? 0 : shared_.size(), 0.0);
}

void Body::set_element_range(int begin, int end)
{
  elem_begin_ = begin;
  elem_end_ = end;
}

/* ---------------------------------------------------------------------- */

void Body::open_reaction_group(int group)
{
  if (group >= 0 && 3 * (group + 1) > static_cast<int>(reactions_.size()))
    reactions_.resize(3 * (group + 1), 0.0);
}

void Body::set_fixed(const std::vector<int>& nodes, int mask, int group)
{
  for (int n : nodes) {
    held_[n] = bc_[n] == NodeBc::Partial ? (held_[n] | mask) : mask;
    bc_[n] = held_[n] == 7 ? NodeBc::Fixed : NodeBc::Partial;
    bc_group_[n] = group;
    for (int d = 0; d < 3; ++d)
      if (mask >> d & 1) component_group_[3 * n + d] = group;
  }
  open_reaction_group(group);
}

void Body::set_prescribed_velocity(const std::vector<int>& nodes, const double v[3], double ramp,
                                   int group, int mask)
{
  for (int n : nodes) {
    if (mask == 7) {
      bc_[n] = NodeBc::Prescribed;
      held_[n] = 7;
    } else {
      held_[n] = static_cast<std::uint8_t>((bc_[n] == NodeBc::Free ? 0 : held_[n]) | mask);
      bc_[n] = NodeBc::Partial;
    }
    ramp_[n] = ramp;
    bc_group_[n] = group;
    for (int d = 0; d < 3; ++d)
      if (mask >> d & 1) {
        component_group_[3 * n + d] = group;
        v_prescribed_[3 * n + d] = v[d];
      }
  }
  open_reaction_group(group);
}

void Body::set_velocity(const std::vector<int>& nodes, const double v[3], int mask)
{
  for (int n : nodes)
    for (int d = 0; d < 3; ++d)
      if (mask >> d & 1) v_[3 * n + d] = v[d];
}

void Body::impose_velocity_conditions()
{
  for (int n = 0; n < num_nodes(); ++n)
    if (bc_[n] == NodeBc::Fixed)
      for (int d = 0; d < 3; ++d)
        v_[3 * n + d] = 0;
    else if (bc_[n] == NodeBc::Prescribed)
      for (int d = 0; d < 3; ++d)
        v_[3 * n + d] = v_prescribed_[3 * n + d] * ramp_factor(n, time_);
    else if (bc_[n] == NodeBc::Partial)
      for (int d = 0; d < 3; ++d)
        if (held_[n] >> d & 1) v_[3 * n + d] = v_prescribed_[3 * n + d] * ramp_factor(n, time_);
}

/* ---------------------------------------------------------------------- */

void Body::move_rigid()
{
  motion_.evaluate(time_, mesh_.X.data(), num_nodes(), x_.data(), v_.data());
}

void Body::half_kick_drift(double dt)
{
  last_dt_ = dt; // the strain rate of rate-dependent materials at the next force evaluation
  const int nn = num_nodes();
  const double half = 0.5 * dt;
  const bool axisym = space_.axisymmetric() && !rigid_;
  for (int n = 0; n < nn; ++n) {
    double* v = &v_[3 * n];
    double* x = &x_[3 * n];
    if (bc_[n] == NodeBc::Free) {
      const double s = half * inv_mass_[n];
      const double* f = &f_[3 * n];
      v[0] += s * f[0];
      v[1] += s * f[1];
      v[2] += s * f[2];
      if (axisym && x[0] + dt * v[0] < 0) shield_drift(n);
    } else if (bc_[n] == NodeBc::Fixed) {
      continue;
    } else if (bc_[n] == NodeBc::Partial) {
      // Free components are kicked; held ones move at their prescribed velocity (at mid-step
      // when ramped, like a Prescribed node; 0 where `fixed` holds them, so x stays put).
      const double s = half * inv_mass_[n];
      const double r = ramp_[n] > 0 ? ramp_factor(n, time_ - 0.5 * dt) : 0.0;
      for (int d = 0; d < 3; ++d) {
        if (!(held_[n] >> d & 1)) {
          v[d] += s * f_[3 * n + d];
          if (d == 0 && axisym && x[0] + dt * v[0] < 0) shield_drift(n);
        } else if (ramp_[n] > 0) {
          v[d] = v_prescribed_[3 * n + d] * r;
        }
        x[d] += dt * v[d];
      }
      continue;
    } else if (ramp_[n] > 0) { // prescribed, ramped: the velocity at mid-step
      const double r = ramp_factor(n, time_ - 0.5 * dt);
      for (int d = 0; d < 3; ++d)
        v[d] = v_prescribed_[3 * n + d] * r;
    }
    x[0] += dt * v[0];
    x[1] += dt * v[1];
    x[2] += dt * v[2];
  }
}

/* ----------------------------------------------------------------------
   axis shield (axisymmetric bodies): x = r >= 0. A node whose drift would
   cross the axis is stopped on it (its radial velocity, and the radial
   kinetic energy with it, taken by the shield: a perfectly inelastic,
   frictionless stop); a node resting on the axis is held there while its
   force pushes it inward (a reaction that does no work: the node does not
   move radially) and leaves as soon as the force pulls it out.
------------------------------------------------------------------------- */

void Body::shield_drift(int n)
{
  double* v = &v_[3 * n];
  if (counted(n)) {
    shield_work_ -= 0.5 * mass_[n] * v[0] * v[0];
    ++shield_hits_;
  }
  v[0] = 0;
  x_[3 * n] = 0; // the drift adds dt * 0
}

void Body::shield_forces()
{
  for (int n = 0; n < num_nodes(); ++n) {
    const bool radial_free =
        bc_[n] == NodeBc::Free || (bc_[n] == NodeBc::Partial && !(held_[n] & 1));
    if (radial_free && x_[3 * n] <= 0 && v_[3 * n] <= 0 && f_[3 * n] < 0) {
      f_[3 * n] = 0;
    }
  }
}

void Body::half_kick(double dt)
{
  const double half = 0.5 * dt;
  const int nn = num_nodes();
  for (int n = 0; n < nn; ++n) {
    if (bc_[n] == NodeBc::Partial) {
      for (int d = 0; d < 3; ++d)
        if (!(held_[n] >> d & 1)) v_[3 * n + d] += half * inv_mass_[n] * f_[3 * n + d];
      continue;
    }
    if (bc_[n] != NodeBc::Free) continue;
    const double s = half * inv_mass_[n];
    const double* f = &f_[3 * n];
    double* v = &v_[3 * n];
    v[0] += s * f[0];
    v[1] += s * f[1];
    v[2] += s * f[2];
  }
}

void Body::kick_contact_difference(double tau)
{
  double work = 0;
  for (int n = 0; n < num_nodes(); ++n) {
    if (bc_[n] != NodeBc::Free && bc_[n] != NodeBc::Partial) continue;
    for (int d = 0; d < 3; ++d) {
      if (bc_[n] == NodeBc::Partial && (held_[n] >> d & 1)) continue;
      const int k = 3 * n + d;
      const double impulse = tau * (f_contact_prev_[k] - f_contact_[k]);
      const double v0 = v_[k];
      v_[k] += impulse * inv_mass_[n];
      if (counted(n)) work += 0.5 * impulse * (v0 + v_[k]);
    }
  }
  contact_work_ += work;
}

void Body::begin_forces()
{
  std::fill(f_.begin(), f_.end(), 0.0);
  std::swap(f_contact_, f_pending_);
  std::fill(f_pending_.begin(), f_pending_.end(), 0.0);
}

double Body::add_internal_forces(int* first_inverted)
{
  if (rigid_) return 0.0;
  const double energy = space_.add_internal_forces(
      mesh_, x_.data(), elem_begin_, elem_end_, f_.data(), nullptr, first_inverted, state_.data(),
      &damaged_points_, last_dt_, &damaged_elems_, &failed_elems_,
      track_length_ > 0 ? &overstressed_elems_ : nullptr);
  if (viscosity_.on && replay_viscous_) {
    std::copy(viscous_force_prev_.begin(), viscous_force_prev_.end(), viscous_force_.begin());
    space_.add_given_viscous_forces(mesh_, x_.data(), elem_begin_, elem_end_, viscous_force_.data(),
                                    f_.data());
  } else if (viscosity_.on) {
    space_.add_viscous_forces(mesh_, x_.data(), v_.data(), elem_begin_, elem_end_, viscosity_,
                              state_.data(), f_.data(), viscous_force_.data(),
                              viscous_rate_.data());
  }
  replay_viscous_ = false;
  return energy;
}

// Work of the viscous forces f = (q W) b over the last step, trapezoidal like the contact work:
// 0.5 (f_prev + f) . dx with dx = v dt and b . v = D (the step's change of b is neglected).
void Body::add_viscous_work(double dt, bool count_work)
{
  for (int e = elem_begin_; e < elem_end_; ++e) {
    if (count_work)
      viscous_work_[e] -=
          0.5 * (viscous_force_prev_[e] + viscous_force_[e]) * viscous_rate_[e] * dt;
    viscous_force_prev_[e] = viscous_force_[e];
  }
  viscous_evaluated_ = viscous_evaluated_ || count_work;
}

double Body::viscous_work() const
{
  double total = 0;
  for (double w : viscous_work_)
    total += w;
  return total;
}

bool Body::element_plastic_state(std::vector<double>& eps_bar,
                                 std::vector<double>& temperature_rise,
                                 std::vector<double>& plastic_work) const
{
  if (!material_.plastic_model()) return false;
  const int ne = mesh_.num_elems();
  eps_bar.assign(ne, 0.0);
  temperature_rise.assign(ne, 0.0);
  plastic_work.assign(ne, 0.0);
  for (int e = 0; e < ne; ++e) {
    if (!mesh_.active[e]) continue;
    double W = 0;
    for (int q = 0; q < points_per_elem(mesh_.etype[e]); ++q) {
      const double* st = &state_[space_.state_offset(e) + q * kPlasticStateSize];
      const double w = space_.point_weight(mesh_, e, q);
      eps_bar[e] += w * plastic_equivalent_strain(st);
      temperature_rise[e] +=
          w * (plastic_temperature(material_.plastic, st) - material_.plastic.troom);
      plastic_work[e] += w * plastic_dissipated(st);
      W += w;
    }
    if (W > 0) {
      eps_bar[e] /= W;
      temperature_rise[e] /= W;
      plastic_work[e] /= W;
    }
  }
  return true;
}

double Body::element_failure(int e, double normal[3]) const
{
  normal[0] = normal[1] = normal[2] = 0;
  double worst = 0;
  const int per = material_model_info(material_.model).state_per_point;
  if (per == 0) return 0.0;
  for (int q = 0; q < points_per_elem(mesh_.etype[e]); ++q) {
    double n[3];
    const double m = point_failure(material_, &state_[space_.state_offset(e) + q * per], n);
    if (m > worst) {
      worst = m;
      std::copy(n, n + 3, normal);
    }
  }
  return worst;
}

bool Body::element_damaged(int e) const
{
  const int per = material_model_info(material_.model).state_per_point;
  if (per == 0 || !mesh_.active[e]) return false;
  for (int q = 0; q < points_per_elem(mesh_.etype[e]); ++q)
    if (point_damaged(material_, &state_[space_.state_offset(e) + q * per])) return true;
  return false;
}

bool Body::element_yielded(int e) const
{
  if (!material_.plastic_model() || !mesh_.active[e]) return false;
  const int per = material_model_info(material_.model).state_per_point;
  for (int q = 0; q < points_per_elem(mesh_.etype[e]); ++q)
    if (plastic_equivalent_strain(&state_[space_.state_offset(e) + q * per]) > 0) return true;
  return false;
}

int Body::element_failures(std::vector<double>& measure, std::vector<double>& normal) const
{
  const int ne = mesh_.num_elems();
  measure.resize(ne);
  normal.resize(3 * ne);
  const int per = material_model_info(material_.model).state_per_point;
  // The last force evaluation listed the damaged elements when it covered the whole body.
  if (elem_begin_ <= 0 && elem_end_ >= ne) {
    std::fill(measure.begin(), measure.end(), 0.0);
    int count = 0;
    for (int e : damaged_elems_)
      if (mesh_.active[e]) { // an element eroded since then is left out, as below
        measure[e] = element_failure(e, &normal[3 * e]);
        ++count;
      }
    return count;
  }
  int damaged_count = 0;
  for (int e = 0; e < ne; ++e) {
    bool damaged = false;
    if (per > 0 && mesh_.active[e])
      for (int q = 0; q < points_per_elem(mesh_.etype[e]); ++q)
        damaged |= point_damaged(material_, &state_[space_.state_offset(e) + q * per]);
    if (damaged) {
      measure[e] = element_failure(e, &normal[3 * e]);
      ++damaged_count;
    } else {
      measure[e] = 0.0;
    }
  }
  return damaged_count;
}

double Body::dissipated_energy() const
{
  const int per = material_model_info(material_.model).state_per_point;
  if (per == 0) return 0.0;
  double total = 0;
  for (int e = 0; e < mesh_.num_elems(); ++e)
    for (int q = 0; q < points_per_elem(mesh_.etype[e]); ++q)
      total += space_.point_weight(mesh_, e, q) *
               point_dissipation(material_, &state_[space_.state_offset(e) + q * per]);
  return total;
}

void Body::element_energies(std::vector<double>& energy) const
{
  energy.assign(mesh_.num_elems(), 0.0);
  if (rigid_) return;
  std::vector<double> scratch_f(3 * num_nodes(), 0.0), scratch_state(state_);
  space_.add_internal_forces(mesh_, x_.data(), 0, mesh_.num_elems(), scratch_f.data(),
                             energy.data(), nullptr, scratch_state.data());
}

void Body::finish_forces(double strain_energy, const double gravity[3], double dt, bool count_work)
{
  strain_energy_ = strain_energy;
  const int nn = num_nodes();
  double dw_contact = 0, dw_gravity = 0;
  contact_force_total_[0] = contact_force_total_[1] = contact_force_total_[2] = 0;
  for (int n = 0; n < nn; ++n) {
    const bool count = counted(n);
    for (int d = 0; d < 3; ++d) {
      const int k = 3 * n + d;
      if (count) {
        dw_contact += 0.5 * (f_contact_[k] + f_contact_prev_[k]) * v_[k];
        contact_force_total_[d] += f_contact_[k];
      }
      f_[k] += f_contact_[k];
    }
  }
  if (!rigid_) {
    const double g2 = gravity[0] * gravity[0] + gravity[1] * gravity[1] + gravity[2] * gravity[2];
    if (g2 > 0)
      for (int n = 0; n < nn; ++n)
        for (int d = 0; d < 3; ++d) {
          f_[3 * n + d] += mass_[n] * gravity[d];
          if (counted(n)) dw_gravity += mass_[n] * gravity[d] * v_[3 * n + d];
        }
  }
  if (count_work) {
    contact_work_ += dt * dw_contact;
    external_work_ += dt * dw_gravity;
  }
  // f_contact_prev_ keeps this step's contact forces; f_contact_ becomes scratch.
  std::swap(f_contact_prev_, f_contact_);
  if (viscosity_.on && !rigid_) add_viscous_work(dt, count_work);
  if (!reactions_.empty()) add_reactions(dt, count_work);
  if (space_.axisymmetric() && !rigid_) shield_forces();
  for (int n = 0; n < nn; ++n)
    if (bc_[n] == NodeBc::Partial) {
      for (int d = 0; d < 3; ++d)
        if (held_[n] >> d & 1) f_[3 * n + d] = 0;
    } else if (bc_[n] != NodeBc::Free) {
      for (int d = 0; d < 3; ++d)
        f_[3 * n + d] = 0;
    }
}

// The constraint force on a held component is what keeps its prescribed motion: m a - f.
// Their work: the reaction times the node's (mid-step) velocity.
void Body::add_reactions(double dt, bool count_work)
{
  std::fill(reactions_.begin(), reactions_.end(), 0.0);
  double dw = 0;
  for (int n = 0; n < num_nodes(); ++n) {
    if (bc_[n] == NodeBc::Free || !counted(n)) continue;
    const double rate = bc_[n] == NodeBc::Fixed ? 0.0 : ramp_rate(n, time_);
    for (int d = 0; d < 3; ++d) {
      const int g = component_group_[3 * n + d];
      if (g >= 0 && (held_[n] >> d & 1)) {
        const double r = mass_[n] * v_prescribed_[3 * n + d] * rate - f_[3 * n + d];
        reactions_[3 * g + d] += r;
        dw += r * v_[3 * n + d];
      }
    }
  }
  if (count_work) boundary_work_ += dt * dw;
}

double Body::kinetic_energy() const
{
  if (rigid_) return 0.0;
  double ke = 0;
  const int nn = num_nodes();
  for (int n = 0; n < nn; ++n) {
    const double* v = &v_[3 * n];
    if (counted(n)) ke += 0.5 * mass_[n] * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  }
  return ke;
}

double Body::momentum(int d) const
{
  if (rigid_) return 0.0;
  double p = 0;
  for (int n = 0; n < num_nodes(); ++n)
    if (counted(n)) p += mass_[n] * v_[3 * n + d];
  return p;
}

double Body::total_mass() const
{
  double m = 0;
  for (int n = 0; n < num_nodes(); ++n)
    if (counted(n)) m += mass_[n];
  return m;
}

/* ---------------------------------------------------------------------- */

int Body::split_node(const SplitPlan& plan)
{
  const int node = plan.node;
  const int copy = fracdem::split_node(mesh_, stars_, plan);
  const std::vector<int>& to_copy = plan.side_b;
  resize_nodes(copy + 1);
  for (int d = 0; d < 3; ++d) {
    x_[3 * copy + d] = x_[3 * node + d];
    v_[3 * copy + d] = v_[3 * node + d];
    v_prescribed_[3 * copy + d] = v_prescribed_[3 * node + d];
    f_contact_prev_[3 * copy + d] = 0;
    f_pending_[3 * copy + d] = 0;
  }
  bc_[copy] = bc_[node];
  held_[copy] = held_[node];
  ramp_[copy] = ramp_[node];
  bc_group_[copy] = bc_group_[node];
  for (int d = 0; d < 3; ++d)
    component_group_[3 * copy + d] = component_group_[3 * node + d];
  parent_[copy] = node;
  // The copy takes its elements' share of the lumped mass, the node keeps the rest (including
  // that of eroded elements), so the sum is unchanged; the force is shared like the mass, so
  // both parts keep the node's acceleration.
  const double m_before = mass_[node];
  double m_copy = 0;
  for (int e : to_copy) {
    double me[4];
    space_.element_nodal_masses(mesh_, e, me);
    for (int a = 0; a < nodes_per_elem(mesh_.etype[e]); ++a)
      if (mesh_.conn[e][a] == copy) m_copy += me[a];
  }
  m_copy = std::min(m_copy, m_before);
  mass_[copy] = m_copy;
  mass_[node] = m_before - m_copy;
  for (int n : {node, copy})
    inv_mass_[n] = mass_[n] > 0 ? 1.0 / mass_[n] : 0.0;
  const double share = m_before > 0 ? m_copy / m_before : 0.5;
  for (int d = 0; d < 3; ++d) {
    const double fc = f_[3 * node + d] * share;
    f_[3 * copy + d] = fc;
    f_[3 * node + d] -= fc;
  }
  return copy;
}

double Body::erode(const std::vector<int>& elems, bool remove_mass)
{
  double strain = 0, kinetic = 0;
  for (int e : elems) {
    if (!mesh_.active[e]) continue;
    // The energy it held leaves with it; an inverted element's may be garbage: not counted.
    const double en = rigid_ ? 0.0 : space_.element_energy(mesh_, x_.data(), e, state_.data());
    if (std::isfinite(en)) strain += en;
    if (remove_mass) kinetic += remove_element_mass(e);
    mesh_.active[e] = 0;
    ++eroded_.elements;
  }
  if (elems.empty()) return 0.0;
  stars_.build(mesh_); // once per batch: a rebuild is a pass over the mesh
  if (remove_mass) kinetic += release_bare_nodes(elems);
  strain_energy_ -= strain; // until the next force evaluation counts the active elements only
  eroded_.energy += strain + kinetic;
  return strain + kinetic;
}

// Takes element e's share of the lumped mass off its nodes, with its momentum and kinetic energy
// (counted as eroded); the nodes keep their velocity. Returns the kinetic energy removed.
double Body::remove_element_mass(int e)
{
  double me[4];
  space_.element_nodal_masses(mesh_, e, me);
  double kinetic = 0;
  for (int a = 0; a < nodes_per_elem(mesh_.etype[e]); ++a) {
    const int n = mesh_.conn[e][a];
    const bool later = !shared_.empty() && shared_[n]; // settle_shared_masses takes it off
    const double dm = std::min(me[a], later ? mass_[n] - taken_[n] : mass_[n]);
    const double* v = &v_[3 * n];
    if (later) {
      taken_[n] += dm;
    } else {
      mass_[n] -= dm;
      inv_mass_[n] = mass_[n] > 0 ? 1.0 / mass_[n] : 0.0;
    }
    eroded_.mass += dm;
    for (int d = 0; d < 3; ++d)
      eroded_.momentum[d] += dm * v[d];
    kinetic += 0.5 * dm * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  }
  return kinetic;
}

// erosion_mass remove: a node of the eroded elements left without any element keeps neither the
// round-off of its mass nor its velocity: it stops where it is (never 1/0: inv_mass is 0).
double Body::release_bare_nodes(const std::vector<int>& elems)
{
  double kinetic = 0;
  for (int e : elems)
    for (int a = 0; a < nodes_per_elem(mesh_.etype[e]); ++a) {
      const int n = mesh_.conn[e][a];
      if (stars_.begin(n) != stars_.end(n)) continue;
      if (!shared_.empty() && shared_[n]) continue; // other parts may hold elements on it
      kinetic += release_node(n);
    }
  return kinetic;
}

// A node left without elements: its mass (round-off, or what a shared node had left) is counted
// as eroded with its momentum and kinetic energy where the node is counted; it stops.
double Body::release_node(int n)
{
  double* v = &v_[3 * n];
  const double dm = mass_[n];
  double kinetic = 0;
  if (counted(n)) {
    eroded_.mass += dm;
    for (int d = 0; d < 3; ++d)
      eroded_.momentum[d] += dm * v[d];
    kinetic = 0.5 * dm * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  }
  mass_[n] = inv_mass_[n] = 0;
  for (int d = 0; d < 3; ++d) // a held component keeps its prescribed velocity
    if (bc_[n] != NodeBc::Prescribed && !(bc_[n] == NodeBc::Partial && (held_[n] >> d & 1)))
      v[d] = 0;
  return kinetic;
}

double Body::settle_shared_masses(const double* field, int width, int at)
{
  double kinetic = 0;
  for (int n = 0; n < num_nodes(); ++n) {
    if (shared_.empty() || !shared_[n]) continue;
    taken_[n] = 0;
    const double dm = field[static_cast<std::size_t>(width) * n + at];
    if (dm == 0) continue;
    mass_[n] = std::max(mass_[n] - dm, 0.0);
    inv_mass_[n] = mass_[n] > 0 ? 1.0 / mass_[n] : 0.0;
    if (field[static_cast<std::size_t>(width) * n + at + 1] == 0) kinetic += release_node(n);
  }
  eroded_.energy += kinetic;
  return kinetic;
}

/* ----------------------------------------------------------------------
   memory
------------------------------------------------------------------------- */

namespace
{

template <typename T> std::size_t vector_bytes(const std::vector<T>& v)
{
  return v.capacity() * sizeof(T);
}

// A std::map node: the key and value plus about four pointers of tree bookkeeping.
std::size_t set_bytes(const std::map<std::string, std::vector<int>>& sets)
{
  std::size_t b = 0;
  for (const auto& kv : sets)
    b += sizeof(kv) + 4 * sizeof(void*) + kv.first.capacity() + vector_bytes(kv.second);
  return b;
}

std::size_t mesh_bytes(const Mesh& m)
{
  return vector_bytes(m.X) + vector_bytes(m.etype) + vector_bytes(m.conn) + vector_bytes(m.active) +
         vector_bytes(m.region) + set_bytes(m.node_sets) + set_bytes(m.elem_sets);
}

} // namespace

std::size_t Body::memory_bytes() const
{
  std::size_t b = sizeof(*this) + mesh_bytes(mesh_) + space_.memory_bytes();
  for (const std::vector<double>* v :
       {&x_, &v_, &f_, &mass_, &inv_mass_, &f_contact_, &f_contact_prev_, &f_pending_,
        &v_prescribed_, &ramp_, &reactions_, &state_, &viscous_work_, &viscous_force_prev_,
        &viscous_force_, &viscous_rate_})
    b += vector_bytes(*v);
  b += vector_bytes(bc_) + vector_bytes(held_) + vector_bytes(bc_group_) + vector_bytes(parent_) +
       vector_bytes(component_group_);
  b += vector_bytes(stars_.offset) + vector_bytes(stars_.elems);
  b += vector_bytes(elem_parent_) + vector_bytes(cut_nodes_) + vector_bytes(mesh_measure_);
  return b;
}

/* ----------------------------------------------------------------------
   restart record (doubles): version, nn, ne, time, external work, contact work,
   version 1: x, v (3 nn each), active (ne)
   version 2: X, x, v, v_prescribed (3 nn each), bc + 8 held, ramp, group, parent, mass (nn each),
              conn (4 ne), active (ne), nstate, material state (nstate), boundary work
   version 3: version 2, then ne, per element viscous work, last viscous force q W and last
              volumetric strain rate (the stable step's damping; ne each);
              written only with bulk viscosity on, so other bodies keep writing version 2
   version 4: version 2, then the viscous block of version 3 with ne = 0 (and nothing after it)
              when the viscosity is off, then the erosion account (elements, mass, energy,
              momentum x y z), the shield work and the shield hits (8); written only once an
              element eroded or the shield acted, so other bodies keep writing version 2 or 3
   version 5: the header, the growth block of the cuts (fem/body_cut.cpp), then version 4's
              layout (viscous block, ne or 0, and accounts always); written only once an
              element was cut, so other bodies keep writing versions 2 to 4
------------------------------------------------------------------------- */

void Body::set_crack_tracking(double length, double exclusion)
{
  track_length_ = length;
  track_exclusion_ = exclusion;
  track_ = CrackTrackState();
  track_.marked.assign(mesh_.num_elems(), 0);
  track_geo_ = TrackGeometry();
  space_.set_softening_mask(track_.marked);
}

void Body::grow_track_marks()
{
  if (track_length_ <= 0) return;
  const int old = static_cast<int>(track_.marked.size());
  track_.marked.resize(mesh_.num_elems(), 0);
  for (int e = old; e < mesh_.num_elems(); ++e) {
    const int parent = element_parent(e);
    track_.marked[e] = parent >= 0 && parent < old ? track_.marked[parent] : 0;
  }
  space_.set_softening_mask(track_.marked);
}

TrackEvents Body::track_cracks()
{
  if (track_length_ <= 0) return {};
  if (static_cast<int>(track_geo_.area.size()) != mesh_.num_elems())
    track_geo_ = track_geometry(mesh_, parent_);
  TrackInput in;
  in.damaged = &damaged_elems_;
  in.overstressed = &overstressed_elems_;
  in.stress = [this](int e, double s[6]) { element_stress(e, s); };
  in.length = track_length_;
  in.exclusion = track_exclusion_;
  const TrackEvents ev = fracdem::track_cracks(mesh_, track_geo_, in, track_,
                                               [this](int e) { return element_parent(e); });
  if (ev.nucleated > 0 || ev.advanced > 0) space_.set_softening_mask(track_.marked);
  return ev;
}

void Body::set_track_state(CrackTrackState state)
{
  track_ = std::move(state);
  track_.marked.resize(mesh_.num_elems(), 0);
  track_geo_ = TrackGeometry();
  space_.set_softening_mask(track_length_ > 0 ? track_.marked : std::vector<std::uint8_t>());
}

void Body::pack_state(std::vector<double>& buf) const
{
  const int nn = num_nodes(), ne = mesh_.num_elems();
  buf.clear();
  buf.reserve(6 + 17 * nn + 6 * ne + state_.size());
  const bool cut = !cut_nodes_.empty();
  const bool accounts = cut || eroded_.elements > 0 || shield_hits_ > 0;
  const double version = cut ? 5.0 : accounts ? 4.0 : viscosity_.on ? 3.0 : 2.0;
  buf.insert(buf.end(), {version, double(nn), double(ne), time_, external_work_, contact_work_});
  if (cut) pack_growth(buf);
  buf.insert(buf.end(), mesh_.X.begin(), mesh_.X.end());
  buf.insert(buf.end(), x_.begin(), x_.end());
  buf.insert(buf.end(), v_.begin(), v_.end());
  buf.insert(buf.end(), v_prescribed_.begin(), v_prescribed_.end());
  for (int n = 0; n < nn; ++n)
    buf.push_back(static_cast<double>(bc_[n]) + 8.0 * held_[n]);
  buf.insert(buf.end(), ramp_.begin(), ramp_.end());
  buf.insert(buf.end(), bc_group_.begin(), bc_group_.end());
  buf.insert(buf.end(), parent_.begin(), parent_.end());
  buf.insert(buf.end(), mass_.begin(), mass_.end());
  for (int e = 0; e < ne; ++e)
    buf.insert(buf.end(), mesh_.conn[e].begin(), mesh_.conn[e].end());
  buf.insert(buf.end(), mesh_.active.begin(), mesh_.active.end());
  buf.push_back(static_cast<double>(state_.size()));
  buf.insert(buf.end(), state_.begin(), state_.end());
  buf.push_back(boundary_work_);
  if (viscosity_.on) {
    buf.push_back(double(ne));
    buf.insert(buf.end(), viscous_work_.begin(), viscous_work_.end());
    buf.insert(buf.end(), viscous_force_prev_.begin(), viscous_force_prev_.end());
    buf.insert(buf.end(), viscous_rate_.begin(), viscous_rate_.end());
  } else if (accounts) {
    buf.push_back(0.0);
  }
  if (!accounts) return;
  buf.insert(buf.end(),
             {double(eroded_.elements), eroded_.mass, eroded_.energy, eroded_.momentum[0],
              eroded_.momentum[1], eroded_.momentum[2], shield_work_, double(shield_hits_)});
}

// The viscous accounts of a version-3 record. A record without them (viscosity off when it was
// written, or older) starts the accounts at zero; one with them needs the viscosity on, or its
// work would drop out of the energy balance.
const double* Body::unpack_viscosity(int version, const double* p)
{
  if (version < 3) return p;
  const int ne = static_cast<int>(*p++);
  if (ne == 0) return p; // version 4 of a body without viscosity
  if (!viscosity_.on)
    throw std::runtime_error("restart file holds the work of a bulk viscosity but this body has "
                             "'bulk_viscosity off'; give it bulk viscosity as the run that wrote "
                             "it had");
  std::copy(p, p + ne, viscous_work_.begin());
  std::copy(p + ne, p + 2 * ne, viscous_force_prev_.begin());
  std::copy(p + 2 * ne, p + 3 * ne, viscous_rate_.begin());
  viscous_evaluated_ = true;
  return p + 3 * ne;
}

void Body::unpack_state(const double* buf)
{
  const int version = static_cast<int>(buf[0]);
  const int nn = static_cast<int>(buf[1]), ne = static_cast<int>(buf[2]);
  const int mesh_nodes = std::count(parent_.begin(), parent_.end(), -1);
  const double* p = buf + 6;
  if (version == 5) p = unpack_growth(p, ne); // throws when ne does not grow from this mesh
  if (version < 1 || version > 5 || ne != mesh_.num_elems() ||
      (version == 1 && nn != num_nodes()) || (version >= 2 && nn < mesh_nodes))
    throw std::runtime_error("restart file holds a body with " + std::to_string(nn) + " nodes / " +
                             std::to_string(ne) + " elements but the mesh has " +
                             std::to_string(mesh_nodes) + " / " +
                             std::to_string(mesh_.num_elems()));
  time_ = buf[3];
  external_work_ = buf[4];
  contact_work_ = buf[5];
  if (version >= 2) {
    mesh_.X.assign(p, p + 3 * nn);
    p += 3 * nn;
  }
  resize_nodes(nn);
  std::copy(p, p + 3 * nn, x_.begin());
  std::copy(p + 3 * nn, p + 6 * nn, v_.begin());
  p += 6 * nn;
  if (version >= 2) {
    std::copy(p, p + 3 * nn, v_prescribed_.begin());
    p += 3 * nn;
    for (int n = 0; n < nn; ++n) {
      bc_[n] = static_cast<NodeBc>(static_cast<int>(p[n]) % 8);
      held_[n] = static_cast<std::uint8_t>(static_cast<int>(p[n]) / 8);
    }
    std::copy(p + nn, p + 2 * nn, ramp_.begin());
    for (int n = 0; n < nn; ++n)
      bc_group_[n] = static_cast<int>(p[2 * nn + n]);
    p += 2 * nn;
    for (int n = 0; n < nn; ++n)
      parent_[n] = static_cast<int>(p[nn + n]);
    for (int n = 0; n < nn; ++n)
      if (parent_[n] >= 0) // a split copy: its parent's groups (parents precede their copies)
        for (int d = 0; d < 3; ++d)
          component_group_[3 * n + d] = component_group_[3 * parent_[n] + d];
      else
        cut_node_groups(n); // a cut node: those of its edge's first end (which precedes it)
    std::copy(p + 2 * nn, p + 3 * nn, mass_.begin());
    p += 3 * nn;
    for (int e = 0; e < ne; ++e)
      for (int a = 0; a < 4; ++a)
        mesh_.conn[e][a] = static_cast<int>(p[4 * e + a]);
    p += 4 * ne;
    // Split nodes join the node sets of their parents, cut nodes those of both their edge's
    // ends (both precede the node).
    for (int n = 0; n < nn; ++n) {
      if (parent_[n] < 0) {
        join_cut_node_sets(n);
        continue;
      }
      for (auto& set : mesh_.node_sets) {
        std::vector<int>& s = set.second;
        if (std::binary_search(s.begin(), s.end(), parent_[n]))
          s.insert(std::upper_bound(s.begin(), s.end(), n), n);
      }
    }
    if (version == 5) restore_cut_elements();
  }
  for (int e = 0; e < ne; ++e)
    mesh_.active[e] = p[e] != 0.0;
  p += ne;
  if (version >= 2) {
    const int nstate = static_cast<int>(*p++);
    if (nstate != static_cast<int>(state_.size()))
      throw std::runtime_error("restart file holds " + std::to_string(nstate) +
                               " material-state values but this body's material has " +
                               std::to_string(state_.size()) + "; use the same 'material'");
    std::copy(p, p + nstate, state_.begin());
    boundary_work_ = p[nstate];
    p += nstate + 1;
  }
  p = unpack_viscosity(version, p);
  eroded_ = ErosionAccount();
  shield_work_ = 0;
  shield_hits_ = 0;
  if (version >= 4) {
    eroded_.elements = static_cast<int>(p[0]);
    eroded_.mass = p[1];
    eroded_.energy = p[2];
    std::copy(p + 3, p + 6, eroded_.momentum);
    shield_work_ = p[6];
    shield_hits_ = static_cast<long>(p[7]);
  }
  stars_.build(mesh_);
  if (version == 1) derive_masses(); // masses of the whole mesh, as that version's runs had
  for (int n = 0; n < nn; ++n)
    inv_mass_[n] = mass_[n] > 0 ? 1.0 / mass_[n] : 0.0;
}

Body::Accounts Body::accounts() const
{
  Accounts a;
  a.time = time_;
  a.external = external_work_;
  a.contact = contact_work_;
  a.boundary = boundary_work_;
  a.shield_work = shield_work_;
  a.shield_hits = static_cast<double>(shield_hits_);
  return a;
}

void Body::set_accounts(const Accounts& a)
{
  time_ = a.time;
  external_work_ = a.external;
  contact_work_ = a.contact;
  boundary_work_ = a.boundary;
  shield_work_ = a.shield_work;
  shield_hits_ = static_cast<long>(a.shield_hits);
}

void Body::set_node_motion(int n, const double* xv)
{
  std::copy(xv, xv + 3, &x_[3 * n]);
  std::copy(xv + 3, xv + 6, &v_[3 * n]);
}

int Body::element_record_size(int e) const
{
  return space_.state_offset(e + 1) - space_.state_offset(e) + (viscosity_.on ? 3 : 0);
}

void Body::pack_element(int e, double* out) const
{
  const int n = element_record_size(e) - (viscosity_.on ? 3 : 0);
  const double* state = state_.data() + space_.state_offset(e);
  std::copy(state, state + n, out);
  if (!viscosity_.on) return;
  out[n] = viscous_work_[e];
  out[n + 1] = viscous_force_prev_[e];
  out[n + 2] = viscous_rate_[e];
}

void Body::unpack_element(int e, const double* in)
{
  const int n = element_record_size(e) - (viscosity_.on ? 3 : 0);
  std::copy(in, in + n, state_.data() + space_.state_offset(e));
  if (!viscosity_.on) return;
  viscous_work_[e] = in[n];
  viscous_force_prev_[e] = in[n + 1];
  viscous_rate_[e] = in[n + 2];
  viscous_evaluated_ = true;
}

void Body::pack_node(int n, double* out) const
{
  const std::vector<double>* vec3[] = {&mesh_.X, &x_, &v_, &f_, &f_contact_prev_, &v_prescribed_};
  for (const std::vector<double>* a : vec3)
    out = std::copy(&(*a)[3 * n], &(*a)[3 * n] + 3, out);
  *out++ = static_cast<double>(bc_[n]) + 8.0 * held_[n];
  *out++ = ramp_[n];
  *out++ = bc_group_[n];
  for (int d = 0; d < 3; ++d)
    *out++ = component_group_[3 * n + d];
  *out = mass_[n];
}

void Body::unpack_node(int n, const double* in)
{
  std::vector<double>* vec3[] = {&mesh_.X, &x_, &v_, &f_, &f_contact_prev_, &v_prescribed_};
  for (std::vector<double>* a : vec3) {
    std::copy(in, in + 3, &(*a)[3 * n]);
    in += 3;
  }
  bc_[n] = static_cast<NodeBc>(static_cast<int>(in[0]) % 8);
  held_[n] = static_cast<std::uint8_t>(static_cast<int>(in[0]) / 8);
  ramp_[n] = in[1];
  bc_group_[n] = static_cast<int>(in[2]);
  for (int d = 0; d < 3; ++d)
    component_group_[3 * n + d] = static_cast<int>(in[3 + d]);
  mass_[n] = in[6];
  inv_mass_[n] = mass_[n] > 0 ? 1.0 / mass_[n] : 0.0;
}

Body::Outputs Body::outputs() const
{
  Outputs o;
  o.strain_energy = strain_energy_;
  std::copy(contact_force_total_, contact_force_total_ + 3, o.contact_force_total);
  o.reactions = reactions_;
  o.eroded = eroded_;
  return o;
}

void Body::set_outputs(const Outputs& o)
{
  strain_energy_ = o.strain_energy;
  std::copy(o.contact_force_total, o.contact_force_total + 3, contact_force_total_);
  if (o.reactions.size() == reactions_.size()) reactions_ = o.reactions;
  eroded_ = o.eroded;
}

void Body::set_damage(int damaged_points, std::vector<int> failed)
{
  damaged_points_ = damaged_points;
  failed_elems_ = std::move(failed);
}

} // namespace fracdem
