#include "ccomp/kinematics/chain.hpp"

#include <cmath>

namespace ccomp::kinematics {

ChainData::ChainData(const ChainModel& model)
    : work_error(model.workpiece.joints.size()),
      tool_error(model.tool.joints.size()),
      work_oMi(model.workpiece.joints.size()),
      tool_oMi(model.tool.joints.size()),
      J_q(6, static_cast<Eigen::Index>(model.nq)),
      J_work_error(model.workpiece.joints.size()),
      J_tool_error(model.tool.joints.size()),
      J_q_work_(6, static_cast<Eigen::Index>(model.nq)),
      J_q_tool_(6, static_cast<Eigen::Index>(model.nq)) {
  auto prepare = [](const Chain& chain, SideCache& cache) {
    const std::size_t n = chain.joints.size();
    cache.links.resize(n);
    cache.errors.assign(n, Pose{Mat3::Constant(std::nan("")), Vec3::Zero()});  // matches no pose
    cache.q.assign(n, 0.0);
    for (const Joint& j : chain.joints) cache.offset_only.push_back(j.placement.R.isIdentity(0.0) ? 1 : 0);
  };
  prepare(model.workpiece, work_cache_);
  prepare(model.tool, tool_cache_);
}

Pose joint_motion(const Joint& joint, double q, Vec6* J) {
  switch (joint.type) {
    case JointType::linear:
      if (J) *J << joint.direction, Vec3::Zero();
      return Pose::translation(q * joint.direction);
    case JointType::rotary:
      // Jr(q d) d = d for any rotation about d.
      if (J) *J << Vec3::Zero(), joint.direction;
      return Pose{so3_exp(q * joint.direction), Vec3::Zero()};
    case JointType::fixed:
      break;
  }
  if (J) J->setZero();
  return Pose::identity();
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

/// link = placement * motion(q) * error, skipping the products by identities that machine
/// files make the rule: placements are offsets, a linear motion is a translation.
void set_link_pose(const Joint& j, bool offset_only, double q, const Pose& error, Pose& link) {
  Pose m = j.placement;  // placement * motion
  switch (j.type) {
    case JointType::linear:
      if (offset_only) {
        link.R = error.R;
        link.t = m.t + q * j.direction + error.t;
        return;
      }
      m.t += j.placement.R * (q * j.direction);
      break;
    case JointType::rotary:
      m.R = offset_only ? so3_exp(q * j.direction) : Mat3(j.placement.R * so3_exp(q * j.direction));
      break;
    case JointType::fixed:
      if (offset_only) {
        link.R = error.R;
        link.t = m.t + error.t;
        return;
      }
      break;
  }
  compose_into(m, error, link);
}

bool same(const Pose& a, const Pose& b) {
  return a.R == b.R && a.t == b.t;
}

/// Composes one side, base to end. With `J_end`, fills for each link the Jacobian of the
/// end pose w.r.t. a right perturbation of the link's error pose (Ad of the suffix
/// inverse), and adds the link's axis motion into J_q_side.
const Pose& compose_side(const Chain& chain, const std::vector<Pose>& errors, const Eigen::Ref<const VecQ>& q,
                  std::vector<Pose>& oMi, ChainData::SideCache& cache, std::vector<Mat6>* J_error,
                  Eigen::Matrix<double, 6, Eigen::Dynamic>* J_q) {
  const std::size_t n = chain.joints.size();
  std::vector<Pose>& links = cache.links;
  bool changed = false;  // a link before this one changed: the poses from here on must follow
  for (std::size_t i = 0; i < n; ++i) {
    const Joint& j = chain.joints[i];
    const double qi = j.type == JointType::fixed ? 0.0 : q[static_cast<Eigen::Index>(j.axis)];
    if (qi != cache.q[i] || !same(errors[i], cache.errors[i])) {
      set_link_pose(j, cache.offset_only[i] != 0, qi, errors[i], links[i]);
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
  if (!J_error) return oM;
  J_q->setZero();
  Pose suffix;  // links i+1 .. n-1
  for (std::size_t k = n; k-- > 0;) {
    const Mat6 Ad_suffix_inv = adjoint(inverse(suffix));
    (*J_error)[k] = Ad_suffix_inv;
    const Joint& j = chain.joints[k];
    if (j.type != JointType::fixed) {
      Vec6 Jm;
      (void)joint_motion(j, q[static_cast<Eigen::Index>(j.axis)], &Jm);
      // motion * Exp(tau) * error = motion * error * Exp(Ad(error^-1) tau)
      J_q->col(static_cast<Eigen::Index>(j.axis)) += Ad_suffix_inv * adjoint(inverse(errors[k])) * Jm;
    }
    suffix = compose(links[k], suffix);
  }
  return oM;
}

}  // namespace

NominalData::NominalData(const ChainModel& model) {
  auto links = [](const Chain& chain) {
    std::vector<Link> out;
    for (const Joint& j : chain.joints) {
      Link l;
      l.offset_only = j.placement.R.isIdentity(0.0);
      l.q = 0.0;
      l.R_motion = j.type == JointType::rotary ? so3_exp(0.0 * j.direction) : Mat3::Identity();
      out.push_back(l);
    }
    return out;
  };
  work_links_ = links(model.workpiece);
  tool_links_ = links(model.tool);
}

namespace {

/// One side of the perfect machine, base to end: the products error_matrix() makes with
/// identity error poses, without those factors (multiplying by them is exact).
Pose nominal_side(const Chain& chain, std::vector<NominalData::Link>& links, const Eigen::Ref<const VecQ>& q) {
  Pose oM;
  for (std::size_t i = 0; i < chain.joints.size(); ++i) {
    const Joint& j = chain.joints[i];
    NominalData::Link& l = links[i];
    const double qi = j.type == JointType::fixed ? 0.0 : q[static_cast<Eigen::Index>(j.axis)];
    Pose link = j.placement;  // placement * motion
    if (j.type == JointType::linear) {
      link.t = l.offset_only ? Vec3(j.placement.t + qi * j.direction)
                             : Vec3(j.placement.t + j.placement.R * (qi * j.direction));
    } else if (j.type == JointType::rotary) {
      if (qi != l.q) l.q = qi, l.R_motion = so3_exp(qi * j.direction);
      if (l.offset_only)
        link.R = l.R_motion;
      else
        link.R = j.placement.R * l.R_motion;
    }
    if (i == 0) {
      oM = link;
    } else {
      oM.t += oM.R * link.t;
      if (j.type == JointType::rotary || !l.offset_only) oM.R = Mat3(oM.R * link.R);
    }
  }
  return oM;
}

}  // namespace

void nominal_poses(const ChainModel& model, NominalData& data, const Eigen::Ref<const VecQ>& q) {
  data.oMp = nominal_side(model.workpiece, data.work_links_, q);
  data.oMtool = nominal_side(model.tool, data.tool_links_, q);
  data.E = compose(inverse(data.oMp), data.oMtool);
}

void error_matrix(const ChainModel& model, ChainData& data, const Eigen::Ref<const VecQ>& q, bool jacobians) {
  auto& Jq_work = data.J_q_work_;
  auto& Jq_tool = data.J_q_tool_;
  const Pose& oMp = compose_side(model.workpiece, data.work_error, q, data.work_oMi, data.work_cache_,
                                 jacobians ? &data.J_work_error : nullptr, &Jq_work);
  const Pose& oMtool = compose_side(model.tool, data.tool_error, q, data.tool_oMi, data.tool_cache_,
                                    jacobians ? &data.J_tool_error : nullptr, &Jq_tool);
  Mat6 J_inv, J_a, J_b;
  const Pose pMo = inverse(oMp, jacobians ? &J_inv : nullptr);
  data.E = compose(pMo, oMtool, jacobians ? &J_a : nullptr, jacobians ? &J_b : nullptr);
  data.oMp = oMp;  // copied last: just composed, they are still being stored
  data.oMtool = oMtool;
  if (!jacobians) return;
  const Mat6 J_E_oMp = J_a * J_inv;  // through the inverse of the workpiece side
  for (Mat6& J : data.J_work_error) J = J_E_oMp * J;
  for (Mat6& J : data.J_tool_error) J = J_b * J;
  data.J_q.noalias() = J_E_oMp * Jq_work;
  data.J_q.noalias() += J_b * Jq_tool;
}

}  // namespace ccomp::kinematics
