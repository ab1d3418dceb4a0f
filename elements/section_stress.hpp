// Stress resultants of a beam section and the stresses they cause in round tubes, frames and
// custom sections: normal, shear, von Mises, and the utilization against a yield stress.
#pragma once

#include "elements/section.hpp"

#include <array>
#include <limits>
#include <span>

namespace latticedyn {

/// Resultants on a section's positive face (outward normal +x, the element's axis) from the part
/// of the member beyond it, in the element frame (y, z the section's principal axes): axial force
/// N (tension positive), shear forces Qy, Qz, torque T, bending moments My, Mz. A cantilever along
/// x with a tip load -P e_z has Qz = -P and My(s) = P (L - s): My > 0 stretches the +z fibres.
template <class S>
struct SectionForcesT {
  S N{0.0}, Qy{0.0}, Qz{0.0}, T{0.0}, My{0.0}, Mz{0.0};
};
using SectionForces = SectionForcesT<double>;

/// The largest stresses of a section under its resultants [Pa].
struct SectionStress {
  double normal = 0.0;     ///< largest |sigma| (axial plus bending)
  double shear = 0.0;      ///< largest |tau| (shear force plus torsion)
  double von_mises = 0.0;  ///< largest sqrt(sigma^2 + 3 tau^2) over the section's checked points (a tube's whole fibre)
};

/// Stresses at the checked points of the section: round tubes over their whole outer fibre, each
/// stress at its exact maximum on the circle (von Mises's as a trust-region subproblem)
/// (sigma = N/A + My z/Iy - Mz y/Iz; tau = T r/J plus the shear force's k (Q . t)/A along the
/// tangent t, k = 4/3 (ro^2 + ro ri + ri^2)/(ro^2 + ri^2), 2 for a thin tube, 4/3 solid); frames at
/// the four corners and the four wall middles (Bredt's torsion T/(2 A_m t), the shear force's
/// Q S/(I 2t) in the walls parallel to it; solid rectangles 1.5 Q/A and Roark's torsion); custom
/// sections at the corners (+-fibre_y, +-fibre_z) with T r_max/J + |Q|/(kappa A), or NaN when
/// their fibres are not given.
SectionStress section_stress(const SectionProperties& section, double poisson_ratio, const SectionForces& f);

/// What the results record of one member: its resultants at both ends (the T-beam's vary
/// linearly between them), its largest von Mises stress over both ends and its utilization,
/// von Mises over the material's yield stress (NaN without one or without a stress).
struct MemberStress {
  std::array<SectionForces, 2> end{};
  double von_mises = std::numeric_limits<double>::quiet_NaN();
  double utilization = std::numeric_limits<double>::quiet_NaN();
};

/// The member's record from its end resultants (and any points between, for elements whose
/// moments are not linear).
MemberStress member_stress(const SectionProperties& section, const Material& material, const SectionForces& end1,
                           const SectionForces& end2, std::span<const SectionForces> between = {});

/// A bar's (strut tie's, rope's) record: the axial force alone.
MemberStress bar_stress(const SectionProperties& section, const Material& material, double axial_force);

}  // namespace latticedyn
