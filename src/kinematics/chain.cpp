#include "ccomp/kinematics/chain.hpp"

#include <cmath>

namespace ccomp::kinematics {

ChainData::ChainData(const ChainModel& model)
    : work_error(model.workpiece.joints.size()),
      tool_error(model.tool.joints.size()),
      work_location(model.workpiece.joints.size()),
      tool_location(model.tool.joints.size()),
      work_oMi(model.workpiece.joints.size()),
      tool_oMi(model.tool.joints.size()),
      J_q(6, static_cast<Eigen::Index>(model.nq)),
      J_work_error(model.workpiece.joints.size()),
      J_tool_error(model.tool.joints.size()),
      J_work_location(model.workpiece.joints.size()),
      J_tool_location(model.tool.joints.size()),
      J_q_work_(6, static_cast<Eigen::Index>(model.nq)),
      J_q_tool_(6, static_cast<Eigen::Index>(model.nq)) {
  auto prepare = [](const Chain& chain, SideCache& cache) {
    const std::size_t n = chain.joints.size();
    cache.links.resize(n);
    cache.errors.assign(n, Pose{Mat3::Constant(std::nan("")), Vec3::Zero()});  // matches no pose
    cache.locations.assign(n, Pose{});
    cache.located.assign(n, 0);
    for (const Joint& j : chain.joints) cache.lines.push_back(j.direction);
    cache.q.assign(n, 0.0);
    for (const Joint& j : chain.joints) cache.offset_only.push_back(j.placement.R.isIdentity(0.0) ? 1 : 0);
  };
  prepare(model.workpiece, work_cache_);
  prepare(model.tool, tool_cache_);
}

namespace {

/// out = a * b, written in place: the chain's innermost operation. (A pose copied right
/// after it was stored piecewise waits for the stores to retire, as store forwarding
/// cannot join them: the chain's poses are written where they stay and read from there.)
inline void compose_into(const Pose& a, const Pose& b, Pose& out) {
  out.R.noalias() = a.R * b.R;
  out.t.noalias() = a.R * b.t;
  out.t += a.t;
}

[[gnu::always_inline]] inline bool is_identity(const Pose& X) {
  return X.t.isZero(0.0) && X.R.isIdentity(0.0);
}

/// link = placement * motion(q) * error, skipping the products by identities that machine
/// files make the rule: placements are offsets, a linear motion is a translation. A
/// location other than the identity (`located`) moves the joint's line (see chain.hpp);
/// `line` is a linear joint's direction turned by it.
[[gnu::always_inline]] inline void set_link_pose(const Joint& j, bool offset_only, double q, bool located,
                                                 const Vec3& line, const Pose& location, const Pose& error,
                                                 Pose& link) {
  if (j.type == JointType::linear && offset_only) {  // (most links: no placement to copy)
    const Vec3 travel = located ? Vec3(location.t + q * line) : Vec3(q * j.direction);
    link.R = error.R;
    link.t = j.placement.t + travel + error.t;
    return;
  }
  Pose m = j.placement;  // placement * motion
  switch (j.type) {
    case JointType::linear: {
      const Vec3 travel = located ? Vec3(location.t + q * line) : Vec3(q * j.direction);
      m.t += j.placement.R * travel;
      break;
    }
    case JointType::rotary: {
      const Mat3 turn = so3_exp(q * j.direction);
      if (located) {  // about the real line: location * Rot(q) * location^-1, written out
        const Mat3 turned = location.R * turn;
        const Mat3 about = turned * location.R.transpose();
        const Vec3 shift = location.t - turned * (location.R.transpose() * location.t);
        m.R = offset_only ? about : Mat3(j.placement.R * about);
        m.t = offset_only ? Vec3(j.placement.t + shift) : Vec3(j.placement.t + j.placement.R * shift);
      } else {
        m.R = offset_only ? turn : Mat3(j.placement.R * turn);
      }
      break;
    }
    case JointType::fixed:
      if (located) {
        m = compose(j.placement, location);
        break;
      }
      if (offset_only) {
        link.R = error.R;
        link.t = m.t + error.t;
        return;
      }
      break;
  }
  compose_into(m, error, link);
}

/// A link's axis column: d link / d q in the link's right tangent.
Vec6 link_axis_column(const Joint& j, const Pose& location, const Pose& error) {
  Vec6 column;
  switch (j.type) {
    case JointType::linear:  // travel = t_L + q R_L d, seen through error^-1
      column.head<3>().noalias() = error.R.transpose() * (location.R * j.direction);
      column.tail<3>().setZero();
      return column;
    case JointType::rotary: {  // L Rot(q) L^-1 error: the turn's axis carried by L, seen through error^-1
      Vec6 Jm;
      Jm << Vec3::Zero(), j.direction;  // Jr(q d) d = d for any rotation about d
      return adjoint(inverse(error)) * (adjoint(location) * Jm);
    }
    case JointType::fixed:
      break;
  }
  column.setZero();
  return column;
}

/// The right Jacobian of a link's pose w.r.t. its location pose (right perturbation).
Mat6 link_location_jacobian(const Joint& j, double q, const Pose& location, const Pose& error) {
  Mat6 J;
  switch (j.type) {
    case JointType::linear: {
      // L (+) (rho, theta) moves the travel by R_L rho - q R_L hat(d) theta, which the
      // link's right tangent sees through error^-1.
      const Mat3 to_link = error.R.transpose() * location.R;
      J.setZero();
      J.topLeftCorner<3, 3>() = to_link;
      J.topRightCorner<3, 3>() = -q * to_link * hat(j.direction);
      return J;
    }
    case JointType::rotary: {
      // f(L) = L M L^-1: f(L Exp(tau)) = f(L) Exp(Ad(L) (Ad(M^-1) - I) tau).
      const Pose turn{so3_exp(q * j.direction), Vec3::Zero()};
      return adjoint(inverse(error)) * adjoint(location) * (adjoint(inverse(turn)) - Mat6::Identity());
    }
    case JointType::fixed:
      break;
  }
  return adjoint(inverse(error));
}

[[gnu::always_inline]] inline bool same(const Pose& a, const Pose& b) {
  return a.R == b.R && a.t == b.t;
}

/// Composes one side, base to end. With `J_end`, fills for each link the Jacobian of the
/// end pose w.r.t. a right perturbation of the link's error pose (Ad of the suffix
/// inverse), and adds the link's axis motion into J_q_side. `errors_set` (bit i: link i)
/// and `locations_set` say which poses the caller may have changed (PoseChanges); the
/// others are taken as composed last.
const Pose& compose_side(const Chain& chain, const std::vector<Pose>& errors, const std::vector<Pose>& locations,
                         const Eigen::Ref<const VecQ>& q, std::vector<Pose>& oMi, ChainData::SideCache& cache,
                         ChainJacobians which, std::vector<Mat6>& J_error, std::vector<Mat6>& J_location,
                         Eigen::Matrix<double, 6, Eigen::Dynamic>& J_q, const std::uint64_t* errors_set,
                         bool locations_set) {
  const std::size_t n = chain.joints.size();
  std::vector<Pose>& links = cache.links;
  bool changed = false;  // a link before this one changed: the poses from here on must follow
  for (std::size_t i = 0; i < n; ++i) {
    const Joint& j = chain.joints[i];
    const double qi = j.type == JointType::fixed ? 0.0 : q[static_cast<Eigen::Index>(j.axis)];
    const bool moved_line = locations_set && !same(locations[i], cache.locations[i]);
    if (moved_line) {
      cache.locations[i] = locations[i];
      cache.located[i] = is_identity(locations[i]) ? 0 : 1;
      cache.lines[i] = locations[i].R * j.direction;
    }
    const bool error_set = !errors_set || i >= 64 || (*errors_set >> i & 1U) != 0;
    if (qi != cache.q[i] || moved_line || (error_set && !same(errors[i], cache.errors[i]))) {
      set_link_pose(j, cache.offset_only[i] != 0, qi, cache.located[i] != 0, cache.lines[i], locations[i], errors[i],
                    links[i]);
      cache.q[i] = qi;
      cache.errors[i] = errors[i];
      changed = true;
    }
    if (changed) {
      if (i == 0)
        oMi[i] = links[i];
      else
        compose_into(oMi[i - 1], links[i], oMi[i]);
    }
  }
  static const Pose kIdentity;
  const Pose& oM = n == 0 ? kIdentity : oMi[n - 1];
  if (which == ChainJacobians::none) return oM;
  J_q.setZero();
  Pose suffix;  // links i+1 .. n-1
  for (std::size_t k = n; k-- > 0;) {
    const Mat6 Ad_suffix_inv = adjoint(inverse(suffix));
    const Joint& j = chain.joints[k];
    if (j.type != JointType::fixed)
      J_q.col(static_cast<Eigen::Index>(j.axis)) += Ad_suffix_inv * link_axis_column(j, locations[k], errors[k]);
    J_error[k] = Ad_suffix_inv;  // the error pose is the link's last factor
    if (which == ChainJacobians::all) {
      const double qk = j.type == JointType::fixed ? 0.0 : q[static_cast<Eigen::Index>(j.axis)];
      J_location[k] = Ad_suffix_inv * link_location_jacobian(j, qk, locations[k], errors[k]);
    }
    suffix = compose(links[k], suffix);
  }
  return oM;
}

}  // namespace

NominalData::NominalData(const ChainModel& model) {
  auto side = [](const Chain& chain) {
    Side out;
    for (const Joint& j : chain.joints) {
      if (j.type == JointType::rotary) out.rotary_q.push_back(0.0), out.rotary_axes.push_back(j.axis);
      if (j.type == JointType::linear) out.linear_axes.push_back(j.axis);
    }
    out.columns.assign(out.linear_axes.size(), Vec3::Zero());
    return out;
  };
  work_side_ = side(model.workpiece);
  tool_side_ = side(model.tool);
}

namespace {

/// One side of the perfect machine for its rotary joints' values in q: the products
/// error_matrix() makes with identity error poses, with every linear joint at 0, and each
/// linear joint's column (its direction carried by the rotations before it).
void compose_nominal_side(const Chain& chain, NominalData::Side& side, const Eigen::Ref<const VecQ>& q) {
  Mat3 R = Mat3::Identity();
  Vec3 t = Vec3::Zero();
  std::size_t rotary = 0, linear = 0;
  for (const Joint& j : chain.joints) {
    const bool offset_only = j.placement.R.isIdentity(0.0);
    t += R * j.placement.t;
    if (j.type == JointType::linear)
      side.columns[linear++] = offset_only ? Vec3(R * j.direction) : Vec3(R * (j.placement.R * j.direction));
    if (!offset_only) R = Mat3(R * j.placement.R);
    if (j.type == JointType::rotary) {
      const double qi = q[static_cast<Eigen::Index>(j.axis)];
      side.rotary_q[rotary++] = qi;
      R = Mat3(R * so3_exp(qi * j.direction));
    }
  }
  side.R = R;
  side.t0 = t;
  side.composed = true;
}

/// One side's end pose at q: composed again where a rotary joint moved (`turned` set),
/// else its affine form.
Pose nominal_side(const Chain& chain, NominalData::Side& side, const Eigen::Ref<const VecQ>& q, bool& turned) {
  bool moved = !side.composed;
  for (std::size_t k = 0; k < side.rotary_axes.size(); ++k)
    if (!(q[static_cast<Eigen::Index>(side.rotary_axes[k])] == side.rotary_q[k])) moved = true;
  if (moved) compose_nominal_side(chain, side, q);
  turned = turned || moved;
  // (Summed in a register: a sum kept in the returned pose would be stored and read back
  // at each joint, waiting on the store every time.)
  Vec3 t = side.t0;
  for (std::size_t k = 0; k < side.linear_axes.size(); ++k)
    t += q[static_cast<Eigen::Index>(side.linear_axes[k])] * side.columns[k];
  return Pose{side.R, t};
}

}  // namespace

void nominal_poses(const ChainModel& model, NominalData& data, const Eigen::Ref<const VecQ>& q) {
  bool turned = false;
  data.oMp = nominal_side(model.workpiece, data.work_side_, q, turned);
  data.oMtool = nominal_side(model.tool, data.tool_side_, q, turned);
  // compose(inverse(oMp), oMtool), its rotation kept while no rotary joint moves.
  const Mat3 pRo = data.oMp.R.transpose();
  if (turned) data.E.R = pRo * data.oMtool.R;
  data.E.t = -(data.oMp.R.transpose() * data.oMp.t) + pRo * data.oMtool.t;  // (inverse()'s products, to the bit)
}

void error_matrix(const ChainModel& model, ChainData& data, const Eigen::Ref<const VecQ>& q, ChainJacobians which,
                  const PoseChanges* changes) {
  auto& Jq_work = data.J_q_work_;
  auto& Jq_tool = data.J_q_tool_;
  const bool locations_set = changes == nullptr || changes->locations;
  const Pose& oMp =
      compose_side(model.workpiece, data.work_error, data.work_location, q, data.work_oMi, data.work_cache_, which,
                   data.J_work_error, data.J_work_location, Jq_work, changes ? &changes->work_error : nullptr,
                   locations_set);
  const Pose& oMtool =
      compose_side(model.tool, data.tool_error, data.tool_location, q, data.tool_oMi, data.tool_cache_, which,
                   data.J_tool_error, data.J_tool_location, Jq_tool, changes ? &changes->tool_error : nullptr,
                   locations_set);
  const bool jacobians = which != ChainJacobians::none;
  Mat6 J_inv, J_a, J_b;
  // (Without Jacobians, the inline forms: at every point the job solves.)
  data.E = jacobians ? compose(inverse(oMp, &J_inv), oMtool, &J_a, &J_b) : compose(inverse(oMp), oMtool);
  data.oMp = oMp;  // copied last: just composed, they are still being stored
  data.oMtool = oMtool;
  if (!jacobians) return;
  const Mat6 J_E_oMp = J_a * J_inv;  // through the inverse of the workpiece side
  for (Mat6& J : data.J_work_error) J = J_E_oMp * J;
  for (Mat6& J : data.J_tool_error) J = J_b * J;
  if (which == ChainJacobians::all) {
    for (Mat6& J : data.J_work_location) J = J_E_oMp * J;
    for (Mat6& J : data.J_tool_location) J = J_b * J;
  }
  data.J_q.noalias() = J_E_oMp * Jq_work;
  data.J_q.noalias() += J_b * Jq_tool;
}

}  // namespace ccomp::kinematics
