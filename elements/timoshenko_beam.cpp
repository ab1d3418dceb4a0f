// Co-rotational Timoshenko beam: elastic force and stiffness from the closed-form kernel, closed-
// form inertia and gravity.
#include "elements/timoshenko_beam.hpp"

#include "elements/strain_rate_damping.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace latticedyn {

void BeamProperties::validate() const {
  material.validate();
  section.validate();
  if (!(std::isfinite(length) && length > 0)) throw std::invalid_argument("beam length must be positive");
  if (!std::isfinite(shear_coefficient)) throw std::invalid_argument("shear coefficient must be finite");
}

TimoshenkoBeam::TimoshenkoBeam(const BeamProperties& p) : props_(p) {
  props_.validate();
  const Material& m = p.material;
  const SectionProperties& s = p.section;
  const double L = p.length, E = m.youngs_modulus, G = m.shear_modulus();
  const double kappa = p.shear_coefficient > 0 ? p.shear_coefficient : s.shear_coefficient(m.poisson_ratio);
  props_.shear_coefficient = kappa;
  const double rho = s.effective_density(m);
  mass_ = rho * s.area * L;
  rotary_ = 0.5 * rho * L * Vec3(s.Iy + s.Iz, s.Iy, s.Iz);
  stiffness_.length = L;
  stiffness_.ea = E * s.area / L;
  stiffness_.gj = G * s.torsion_constant / L;
  // Bending about z (deflection along y) uses Iz, about y uses Iy.
  const double phi_z = 12 * E * s.Iz / (kappa * G * s.area * L * L);
  const double phi_y = 12 * E * s.Iy / (kappa * G * s.area * L * L);
  stiffness_.kz[0] = E * s.Iz / (L * (1 + phi_z)) * (4 + phi_z);
  stiffness_.kz[1] = E * s.Iz / (L * (1 + phi_z)) * (2 - phi_z);
  stiffness_.ky[0] = E * s.Iy / (L * (1 + phi_y)) * (4 + phi_y);
  stiffness_.ky[1] = E * s.Iy / (L * (1 + phi_y)) * (2 - phi_y);
}

void TimoshenkoBeam::inertia(std::span<const SlotState<double>> s, const ElementContext& ctx, Eigen::Ref<VecX> r,
                             ElementTangents* t) const {
  const double m6 = mass_ / 6.0;
  const Mat3 J = rotary_.asDiagonal();
  r.segment<3>(0) = m6 * (2 * s[0].acc + s[2].acc) - 3 * m6 * ctx.gravity;
  r.segment<3>(6) = m6 * (s[0].acc + 2 * s[2].acc) - 3 * m6 * ctx.gravity;
  for (int e = 0; e < 2; ++e) {
    const Vec3& w = s[1 + 2 * e].vel;
    r.segment<3>(3 + 6 * e) = J * s[1 + 2 * e].acc + w.cross(J * w);
  }
  if (!t) return;
  t->K.setZero();
  t->C.setZero();
  t->M.setZero();
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b) t->M.block<3, 3>(6 * a, 6 * b) = (a == b ? 2 * m6 : m6) * Mat3::Identity();
  for (int e = 0; e < 2; ++e) {
    const Vec3& w = s[1 + 2 * e].vel;
    t->M.block<3, 3>(3 + 6 * e, 3 + 6 * e) = J;
    t->C.block<3, 3>(3 + 6 * e, 3 + 6 * e) = skew(w) * J - skew<double>(J * w);
  }
}


void TimoshenkoBeam::add_damping(std::span<const SlotState<double>> s, const ElementContext& ctx, Eigen::Ref<VecX> r,
                                 ElementTangents* t) const {
  const RayleighDamping& damping = props_.material.damping;
  if (!damping.active() || ctx.at_rest) return;
  if (damping.alpha > 0) {
    const double a6 = damping.alpha * mass_ / 6.0;
    r.segment<3>(0) += a6 * (2 * s[0].vel + s[2].vel);
    r.segment<3>(6) += a6 * (s[0].vel + 2 * s[2].vel);
    for (int e = 0; e < 2; ++e) r.segment<3>(3 + 6 * e) += damping.alpha * rotary_.cwiseProduct(s[1 + 2 * e].vel);
    if (t) {
      for (int a = 0; a < 2; ++a) {
        for (int b = 0; b < 2; ++b) t->C.block<3, 3>(6 * a, 6 * b).diagonal().array() += (a == b ? 2 : 1) * a6;
        t->C.block<3, 3>(3 + 6 * a, 3 + 6 * a).diagonal() += damping.alpha * rotary_;
      }
    }
  }
  if (damping.beta <= 0) return;
  const MatX Cd = damping.beta * corotational_local_stiffness(stiffness_);
  Vec9 v;
  v << s[2].vel - s[0].vel, s[1].vel, s[3].vel;
  Vec9 f = Vec9::Zero();
  const Vec3 d = s[2].pos - s[0].pos;
  if (!t) {
    using Seeds = EnergyAD<9>::FirstOrder;
    Seeds ad;
    const auto def = corotational_deformation<Seeds::S>(stiffness_, ad.vec(d, 0), ad.rot(s[1].rot, 3), ad.rot(s[3].rot, 6));
    const auto e = corotational_deformation_measures(def);
    add_strain_rate_damping_force<9>(e, Cd, v, f);
    r += expand_force(f);
    return;
  }
  using Seeds = EnergyAD<9>::SecondOrder;
  Seeds ad;
  const auto def = corotational_deformation<Seeds::S>(stiffness_, ad.vec(d, 0), ad.rot(s[1].rot, 3), ad.rot(s[3].rot, 6));
  const auto e = corotational_deformation_measures(def);
  Mat9 K = Mat9::Zero(), C = Mat9::Zero();
  add_strain_rate_damping<9>(e, ad, Cd, v, f, K, C);
  r += expand_force(f);
  add_expanded(K, t->K);
  add_expanded(C, t->C);
}

void TimoshenkoBeam::residual(std::span<const SlotState<double>> s, const ElementContext& ctx, Eigen::Ref<VecX> r) const {
  inertia(s, ctx, r, nullptr);
  Vec9 f;
  elastic_force(s[2].pos - s[0].pos, s[1].rot, s[3].rot, f, nullptr);
  r += expand_force(f);
  add_damping(s, ctx, r, nullptr);
}

void TimoshenkoBeam::tangents(std::span<const SlotState<double>> s, const ElementContext& ctx, ElementTangents& out) const {
  out.resize(12);
  inertia(s, ctx, out.residual, &out);
  Vec9 f;
  Mat9 K;
  elastic_force(s[2].pos - s[0].pos, s[1].rot, s[3].rot, f, &K);
  out.residual += expand_force(f);
  add_expanded(K, out.K);
  add_damping(s, ctx, out.residual, &out);
}

namespace {

// Up to four beams on the lanes of the co-rotational kernel; unused lanes repeat the last beam.
struct BeamLanes {
  CorotationalStiffnessT<Pack4> k;
  Vec3T<Pack4> d;
  Mat3T<Pack4> R1, R2;
  CorotationalForce<Pack4> force;

  BeamLanes(std::span<const Element* const> beams, std::span<const std::span<const SlotState<double>>> states) {
    const int n = static_cast<int>(beams.size());
    if (n < 1 || n > Pack4::kLanes) throw std::logic_error("TimoshenkoBeam: a batch holds one to four beams");
    for (int l = 0; l < Pack4::kLanes; ++l) {
      const int b = std::min(l, n - 1);
      const std::span<const SlotState<double>> s = states[b];
      set_lane(k, l, static_cast<const TimoshenkoBeam&>(*beams[b]).stiffness());
      set_lane(d, l, s[2].pos - s[0].pos);
      set_lane(R1, l, s[1].rot);
      set_lane(R2, l, s[3].rot);
    }
    corotational_internal_force(k, d, R1, R2, force);
  }
};

}  // namespace

void TimoshenkoBeam::residual_batch(std::span<const Element* const> elements,
                                    std::span<const std::span<const SlotState<double>>> states,
                                    const ElementContext& ctx, std::span<VecX> out) const {
  const BeamLanes lanes(elements, states);
  for (std::size_t b = 0; b < elements.size(); ++b) {
    const auto& beam = static_cast<const TimoshenkoBeam&>(*elements[b]);
    out[b].resize(12);
    beam.inertia(states[b], ctx, out[b], nullptr);
    out[b] += expand_force(lane(lanes.force.f, static_cast<int>(b)));
    beam.add_damping(states[b], ctx, out[b], nullptr);
  }
}

void TimoshenkoBeam::tangents_batch(std::span<const Element* const> elements,
                                    std::span<const std::span<const SlotState<double>>> states,
                                    const ElementContext& ctx, std::span<ElementTangents> out) const {
  const BeamLanes lanes(elements, states);
  Eigen::Matrix<Pack4, 9, 9> K9;
  corotational_tangent(lanes.k, lanes.R1, lanes.R2, lanes.force, K9);
  for (std::size_t b = 0; b < elements.size(); ++b) {
    const auto& beam = static_cast<const TimoshenkoBeam&>(*elements[b]);
    ElementTangents& t = out[b];
    t.resize(12);
    beam.inertia(states[b], ctx, t.residual, &t);
    t.residual += expand_force(lane(lanes.force.f, static_cast<int>(b)));
    add_expanded(lane(K9, static_cast<int>(b)), t.K);
    beam.add_damping(states[b], ctx, t.residual, &t);
  }
}

ElementEnergy TimoshenkoBeam::energy(std::span<const SlotState<double>> s, const ElementContext& ctx) const {
  ElementEnergy e;
  const Vec3 &v1 = s[0].vel, &v2 = s[2].vel;
  e.kinetic = mass_ / 6.0 * (v1.squaredNorm() + v1.dot(v2) + v2.squaredNorm());
  for (int k = 0; k < 2; ++k) e.kinetic += 0.5 * s[1 + 2 * k].vel.dot(rotary_.asDiagonal() * s[1 + 2 * k].vel);
  e.gravity_potential = -mass_ * ctx.gravity.dot(0.5 * (s[0].pos + s[2].pos));
  e.strain = strain_energy<double>(s[2].pos - s[0].pos, s[1].rot, s[3].rot);
  return e;
}

std::optional<double> TimoshenkoBeam::axial_force(std::span<const SlotState<double>> s, const ElementContext&) const {
  return stiffness_.ea * ((s[2].pos - s[0].pos).norm() - props_.length);
}

void TimoshenkoBeam::deformed_state(const Vec3& r1, const Vec3& d, const Mat3& R1, const Mat3& R2, double* strain,
                                    double* axial, std::vector<Vec3>* axis, MemberStress* stress) const {
  const CorotationalDeformation<double> def = corotational_deformation<double>(stiffness_, d, R1, R2);
  if (strain) *strain = corotational_strain_energy<double>(stiffness_, def);
  if (axial) *axial = stiffness_.ea * def.u;
  if (stress) {
    const auto ends = corotational_section_forces<double>(stiffness_, def);
    *stress = member_stress(props_.section, props_.material, ends[0], ends[1]);
  }
  if (!axis) return;
  axis->resize(kAxisPoints);
  for (int k = 0; k < kAxisPoints; ++k) (*axis)[k] = corotational_axis_point(def, r1, d, k / (kAxisPoints - 1.0));
}

std::vector<Vec3> TimoshenkoBeam::axis_points(std::span<const SlotState<double>> s, const ElementContext&) const {
  std::vector<Vec3> pts;
  deformed_state(s[0].pos, s[2].pos - s[0].pos, s[1].rot, s[3].rot, nullptr, nullptr, &pts);
  return pts;
}

void TimoshenkoBeam::output(std::span<const SlotState<double>> s, const ElementContext& ctx, ElementOutput& out) const {
  const Vec3 &v1 = s[0].vel, &v2 = s[2].vel;
  out.energy.kinetic = mass_ / 6.0 * (v1.squaredNorm() + v1.dot(v2) + v2.squaredNorm());
  for (int k = 0; k < 2; ++k) out.energy.kinetic += 0.5 * s[1 + 2 * k].vel.dot(rotary_.asDiagonal() * s[1 + 2 * k].vel);
  out.energy.gravity_potential = -mass_ * ctx.gravity.dot(0.5 * (s[0].pos + s[2].pos));
  out.polylines.resize(1);
  out.members.resize(1);
  double axial;
  deformed_state(s[0].pos, s[2].pos - s[0].pos, s[1].rot, s[3].rot, &out.energy.strain, &axial, &out.polylines[0],
                 &out.members[0]);
  out.axial_force = axial;
  out.polyline_axial_forces.clear();
}

}  // namespace latticedyn
