// A double-layer grid space truss (a roof lattice) of strut ties generated in code, with about
// a thousand bars, corner supports on spherical joints and gravity: the benchmark model.
#pragma once

#include "assembly/model_builder.hpp"
#include "elements/strut_tie.hpp"

#include <memory>
#include <vector>

namespace latticedyn::bench {

/// nx x ny top nodes on a 1 m grid, (nx-1) x (ny-1) bottom nodes 0.8 m below the cell centres;
/// top and bottom chords plus four diagonals per cell. 12 x 13 gives 1056 bars.
inline Model space_truss(int nx = 12, int ny = 13) {
  ModelBuilder b;
  b.set_title("double-layer grid space truss");
  b.set_gravity(Vec3(0, 0, -9.81));
  StrutTieProperties p;
  p.material = Material{7800.0, 2.06e11, 0.3, {}, 0.0};
  p.section = round_tube_section(0.04, 0.034);
  p.smoothing = 1e-4;
  const int body = b.add_body("truss", "strut_tie");

  std::vector<int> top(nx * ny), bottom((nx - 1) * (ny - 1));
  std::vector<Vec3> top_pos(top.size()), bottom_pos(bottom.size());
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      top_pos[j * nx + i] = Vec3(i, j, 0.0);
      top[j * nx + i] = b.add_block(DofBlock::translation(top_pos[j * nx + i], Vec3::Zero(), "top"));
    }
  for (int j = 0; j + 1 < ny; ++j)
    for (int i = 0; i + 1 < nx; ++i) {
      bottom_pos[j * (nx - 1) + i] = Vec3(i + 0.5, j + 0.5, -0.8);
      bottom[j * (nx - 1) + i] = b.add_block(DofBlock::translation(bottom_pos[j * (nx - 1) + i], Vec3::Zero(), "bottom"));
    }
  auto bar = [&](int a, const Vec3& pa, int c, const Vec3& pc) {
    StrutTieProperties q = p;
    q.rest_length = (pc - pa).norm();
    b.add_element(body, std::make_shared<StrutTie>(q), {{a}, {c}});
  };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const int k = j * nx + i;
      if (i + 1 < nx) bar(top[k], top_pos[k], top[k + 1], top_pos[k + 1]);
      if (j + 1 < ny) bar(top[k], top_pos[k], top[k + nx], top_pos[k + nx]);
    }
  for (int j = 0; j + 1 < ny; ++j)
    for (int i = 0; i + 1 < nx; ++i) {
      const int k = j * (nx - 1) + i;
      if (i + 2 < nx) bar(bottom[k], bottom_pos[k], bottom[k + 1], bottom_pos[k + 1]);
      if (j + 2 < ny) bar(bottom[k], bottom_pos[k], bottom[k + nx - 1], bottom_pos[k + nx - 1]);
      for (int c : {j * nx + i, j * nx + i + 1, (j + 1) * nx + i, (j + 1) * nx + i + 1})
        bar(bottom[k], bottom_pos[k], top[c], top_pos[c]);
    }
  // Corner supports: spherical joints to the ground, with multipliers (the support forces).
  const int corners[4] = {0, nx - 1, (ny - 1) * nx, ny * nx - 1};
  for (int n = 0; n < 4; ++n) {
    Joint j;
    j.name = "truss.corner" + std::to_string(n);
    j.translation_block = top[corners[n]];
    const int node = b.add_joint(body, j);
    const int ground = b.add_ground_joint("ground.corner" + std::to_string(n), top_pos[corners[n]], Mat3::Identity());
    Constraint c;
    c.name = "support" + std::to_string(n);
    c.type = ConstraintType::spherical;
    c.joint1 = ground;
    c.joint2 = node;
    b.add_constraint(c, false);
  }
  return b.build();
}

}  // namespace latticedyn::bench
