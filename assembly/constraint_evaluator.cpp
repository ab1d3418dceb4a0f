// Constraints of thesis 4.4 in closed form. Every row is w . P (a joint position along a fixed
// direction) or X . Y (two vectors of the joint frames: points, their difference, frame axes), and
// each vector is a sum of at most two terms t + R s (points) or R c (axes) of the free blocks,
// whose variations are those of points of rigid bodies under right perturbations R exp(skew(d)):
//   dV = dt - R skew(s) d_theta,   D_eps[w . dV] = w . R (eps x (d_theta x s)).
// So G, d(G^T lambda)/dq (4-15, 4-19, 4-23) and Gamma follow without automatic differentiation.
#include "assembly/constraint_blocks.hpp"

#include "core/rotation.hpp"

#include <cmath>

namespace latticedyn {

namespace constraint_detail {

int collect_blocks(const ConstraintInputs& in, ConstraintEval& out) {
  const Model& model = *in.model;
  const Constraint& c = *in.constraint;
  int n = 0;
  auto add = [&](int block) {
    if (block < 0 || model.blocks[block].fixed) return;
    for (int k = 0; k < n; ++k)
      if (out.blocks[k] == block) return;
    out.blocks[n++] = block;
  };
  for (int j : {c.joint1, c.joint2}) {
    add(model.joints[j].translation_block);
    add(model.joints[j].rotation_block);
  }
  out.cols = 3 * n;
  return n;
}

}  // namespace constraint_detail

void joint_frame(const Joint& j, const BlockState& t, const BlockState* r, Vec3& pos, Mat3& rot) {
  constraint_detail::frame_of<double>(j, t.pos, r ? &r->rot : nullptr, pos, rot);
}

namespace {

constexpr int kCols = ConstraintEval::kMaxCols;
using Jac = Eigen::Matrix<double, 3, kCols>;
using Sq = Eigen::Matrix<double, kCols, kCols>;
using Row = Eigen::Matrix<double, 1, kCols>;

// A vector of the joint frames: its value, its Jacobian in the constraint's columns, and the
// rotating terms R s that its second variation comes from (sign, rotation column, R, s).
struct FrameVector {
  Vec3 v = Vec3::Zero();
  Jac J = Jac::Zero();
  struct Term {
    double sign;
    int col;  // the rotation block's first column, -1 if it does not move
    Mat3 R;
    Vec3 s;
  };
  Term terms[2];
  int nterms = 0;

  FrameVector operator-(const FrameVector& o) const {
    FrameVector d = *this;
    d.v -= o.v;
    d.J -= o.J;
    for (int k = 0; k < o.nterms; ++k) {
      d.terms[d.nterms] = o.terms[k];
      d.terms[d.nterms++].sign = -o.terms[k].sign;
    }
    return d;
  }
  Vec3 rate(const Eigen::Matrix<double, kCols, 1>& dq) const { return J * dq; }
};

// D_eps[w . dV(q (+) eps)] as a matrix (rows: the virtual displacement, columns: eps):
// (R^T w) s^T - (R^T w . s) I on the rotation block of each term.
void add_second_variation(const FrameVector& V, const Vec3& w, double coeff, Sq& H) {
  for (int k = 0; k < V.nterms; ++k) {
    const FrameVector::Term& t = V.terms[k];
    if (t.col < 0) continue;
    const Vec3 u = t.R.transpose() * w;
    H.block<3, 3>(t.col, t.col) += (coeff * t.sign) * (u * t.s.transpose() - u.dot(t.s) * Mat3::Identity());
  }
}

// w . R (omega x (omega x s)) summed over the terms: the second variation along the motion itself.
double centripetal(const FrameVector& V, const Vec3& w, const ConstraintInputs& in, const ConstraintEval& out) {
  double g = 0.0;
  for (int k = 0; k < V.nterms; ++k) {
    const FrameVector::Term& t = V.terms[k];
    if (t.col < 0) continue;
    const Vec3& om = in.block_state(out.blocks[t.col / 3]).vel;
    g += t.sign * w.dot(t.R * om.cross(om.cross(t.s)));
  }
  return g;
}

struct JointVectors {
  FrameVector position, axis[3];
};

JointVectors joint_vectors(const ConstraintInputs& in, const ConstraintEval& out, int joint) {
  const Joint& j = in.model->joints[joint];
  auto column_of = [&](int block) -> int {
    for (int k = 0; k < out.cols / 3; ++k)
      if (block >= 0 && out.blocks[k] == block) return 3 * k;
    return -1;
  };
  JointVectors jv;
  const BlockState& ts = in.block_state(j.translation_block);
  const int ct = column_of(j.translation_block);
  jv.position.v = ts.pos;
  if (ct >= 0) jv.position.J.block<3, 3>(0, ct) = Mat3::Identity();
  if (j.rotation_block < 0) {
    for (int i = 0; i < 3; ++i) jv.axis[i].v = j.frame.col(i);
    return jv;
  }
  const Mat3& R = in.block_state(j.rotation_block).rot;
  const int cr = column_of(j.rotation_block);
  jv.position.v += R * j.offset;
  jv.position.terms[jv.position.nterms++] = {1.0, cr, R, j.offset};
  if (cr >= 0) jv.position.J.block<3, 3>(0, cr) = -R * skew<double>(j.offset);
  for (int i = 0; i < 3; ++i) {
    FrameVector& a = jv.axis[i];
    const Vec3 c = j.frame.col(i);
    a.v = R * c;
    a.terms[a.nterms++] = {1.0, cr, R, c};
    if (cr >= 0) a.J.block<3, 3>(0, cr) = -R * skew<double>(c);
  }
  return jv;
}

// One row g = coeff X . Y (or coeff w . X when Y is a fixed direction) with its derivatives; its
// second variation goes straight into H = d(G^T lambda)/dq weighted with the row's multiplier.
struct RowTerms {
  double g = 0.0;
  Row G = Row::Zero();
  double gamma = 0.0;  // the second variation along the motion, dq^T (dG/dq) dq
};

struct Second {
  Sq* H = nullptr;       // null: not wanted
  double weight = 0.0;   // lambda of the row
};

void add_dot(const FrameVector& X, const FrameVector& Y, double coeff, Second h, bool velocity,
             const Eigen::Matrix<double, kCols, 1>& dq, const ConstraintInputs& in, const ConstraintEval& out,
             RowTerms& r) {
  r.g += coeff * X.v.dot(Y.v);
  r.G.noalias() += coeff * (Y.v.transpose() * X.J + X.v.transpose() * Y.J);
  if (h.H) {
    const double c = coeff * h.weight;
    add_second_variation(X, Y.v, c, *h.H);
    add_second_variation(Y, X.v, c, *h.H);
    const int n = out.cols;
    h.H->topLeftCorner(n, n).noalias() += c * (X.J.leftCols(n).transpose() * Y.J.leftCols(n) +
                                               Y.J.leftCols(n).transpose() * X.J.leftCols(n));
  }
  if (velocity)
    r.gamma += coeff * (centripetal(X, Y.v, in, out) + centripetal(Y, X.v, in, out) + 2.0 * X.rate(dq).dot(Y.rate(dq)));
}

void add_along(const FrameVector& X, const Vec3& w, double coeff, Second h, bool velocity, const ConstraintInputs& in,
               const ConstraintEval& out, RowTerms& r) {
  r.g += coeff * w.dot(X.v);
  r.G.noalias() += coeff * (w.transpose() * X.J);
  if (h.H) add_second_variation(X, w, coeff * h.weight, *h.H);
  if (velocity) r.gamma += coeff * centripetal(X, w, in, out);
}

}  // namespace

ConstraintEval evaluate_constraint(const ConstraintInputs& in) {
  ConstraintEval out;
  const Constraint& c = *in.constraint;
  out.rows = c.rows();
  constraint_detail::collect_blocks(in, out);
  const int n = out.cols;
  const bool second = in.lambda != nullptr, velocity = in.with_velocity_terms;
  Eigen::Matrix<double, kCols, 1> dq = Eigen::Matrix<double, kCols, 1>::Zero();
  if (velocity)
    for (int k = 0; k < n / 3; ++k) dq.segment<3>(3 * k) = in.block_state(out.blocks[k]).vel;
  const JointVectors j1 = joint_vectors(in, out, c.joint1), j2 = joint_vectors(in, out, c.joint2);
  const int a = c.axis, p = (a + 1) % 3, q = (a + 2) % 3;
  const double u = in.drive.value;

  RowTerms rows[ConstraintEval::kMaxRows];
  // Drive terms of the driven row: g_u, and Gamma's terms in the drive's rates.
  double g_u[ConstraintEval::kMaxRows] = {0, 0, 0, 0, 0, 0};
  double gamma_drive[ConstraintEval::kMaxRows] = {0, 0, 0, 0, 0, 0};
  auto h = [&](int row, double factor = 1.0) {
    return second ? Second{&out.H, factor * in.lambda[row]} : Second{};
  };
  auto position_rows = [&](int first) {  // r1 - r2 = 0
    const FrameVector d = j1.position - j2.position;
    for (int i = 0; i < 3; ++i) add_along(d, Vec3::Unit(i), 1.0, h(first + i), velocity, in, out, rows[first + i]);
  };
  auto aligned_rows = [&](int first) {  // e_y1.e_z2 = e_z1.e_x2 = e_x1.e_y2 = 0
    add_dot(j1.axis[1], j2.axis[2], 1.0, h(first), velocity, dq, in, out, rows[first]);
    add_dot(j1.axis[2], j2.axis[0], 1.0, h(first + 1), velocity, dq, in, out, rows[first + 1]);
    add_dot(j1.axis[0], j2.axis[1], 1.0, h(first + 2), velocity, dq, in, out, rows[first + 2]);
  };
  switch (c.type) {
    case ConstraintType::spherical:
      position_rows(0);
      break;
    case ConstraintType::fixed:
      position_rows(0);
      aligned_rows(3);
      break;
    case ConstraintType::revolute:
      position_rows(0);
      add_dot(j1.axis[p], j2.axis[a], 1.0, h(3), velocity, dq, in, out, rows[3]);
      add_dot(j1.axis[q], j2.axis[a], 1.0, h(4), velocity, dq, in, out, rows[4]);
      if (c.drive >= 0) {
        // g = cos(u) e_q1.e_p2 - sin(u) e_p1.e_p2 = cos(u) A - sin(u) B, so g_u = -sin(u) A - cos(u) B
        // and g_uu = -g.
        const double cu = std::cos(u), su = std::sin(u);
        RowTerms A, B;
        add_dot(j1.axis[q], j2.axis[p], 1.0, h(5, cu), velocity, dq, in, out, A);
        add_dot(j1.axis[p], j2.axis[p], 1.0, h(5, -su), velocity, dq, in, out, B);
        RowTerms& r = rows[5];
        r.g = cu * A.g - su * B.g;
        r.G = cu * A.G - su * B.G;
        r.gamma = cu * A.gamma - su * B.gamma;
        g_u[5] = -su * A.g - cu * B.g;
        if (velocity) {
          const double ud = in.drive.rate;
          const double Gu_dq = -su * A.G.dot(dq.transpose()) - cu * B.G.dot(dq.transpose());
          gamma_drive[5] = 2.0 * Gu_dq * ud - r.g * ud * ud + g_u[5] * in.drive.accel;
        }
      }
      break;
    case ConstraintType::prismatic: {
      // (r1 - r2).e_p1 = (r1 - r2).e_q1 = 0, frames aligned; driven: (r2 - r1).e_a1 - u = 0.
      const FrameVector d = j1.position - j2.position;
      add_dot(d, j1.axis[p], 1.0, h(0), velocity, dq, in, out, rows[0]);
      add_dot(d, j1.axis[q], 1.0, h(1), velocity, dq, in, out, rows[1]);
      aligned_rows(2);
      if (c.drive >= 0) {
        add_dot(d, j1.axis[a], -1.0, h(5), velocity, dq, in, out, rows[5]);
        rows[5].g -= u;
        g_u[5] = -1.0;
        if (velocity) gamma_drive[5] = -in.drive.accel;
      }
      break;
    }
  }

  for (int r = 0; r < out.rows; ++r) {
    out.g(r) = rows[r].g;
    out.G.row(r) = rows[r].G;
    out.g_u(r) = g_u[r];
    if (velocity) {
      out.gamma(r) = rows[r].gamma + gamma_drive[r];
      out.g_dot(r) = rows[r].G.head(n).dot(dq.head(n)) + g_u[r] * in.drive.rate;
    }
  }
  return out;
}

}  // namespace latticedyn
