#include "held_out.hpp"

#include <Eigen/Core>
#include <algorithm>
#include <vector>

#include "symmetric_eigen.hpp"

namespace ccomp::identify::detail {
namespace {

/// Sources are the groups when two or more each carry this share of the candidate.
constexpr double kSourceShare = 0.2;
/// A reading carries the candidate when its columns' energy is above this share of the largest.
constexpr double kSupport = 1e-6;
/// Readings in one source: this many folds of interleaved blocks, each of several blocks.
constexpr int kBlockFolds = 5;
constexpr int kBlocksPerFold = 8;

/// Each reading's group (-1: always fitted on, never scored: it does not carry the
/// candidate). Judged by the columns less what the base takes: a source where the base
/// absorbs the candidate (a table's indexing error at B0 on the laser lines) tells nothing
/// about it.
std::vector<int> groups_of(const Eigen::MatrixXd& columns, const MeasurementSet& data, HeldOut& out) {
  const auto n = columns.rows();
  const Eigen::VectorXd energy = columns.rowwise().squaredNorm();
  const double total = energy.sum(), largest = energy.maxCoeff();
  std::vector<double> share(data.sources.size() + 1, 0.0);
  for (Eigen::Index i = 0; i < n; ++i) share[data.observations[static_cast<std::size_t>(i)].source] += energy[i];
  const auto carrying = std::count_if(share.begin(), share.end(), [&](double s) { return s >= kSourceShare * total; });
  std::vector<int> group(static_cast<std::size_t>(n), -1);
  if (carrying >= 2) {
    out.by = HeldOutBy::source;
    out.groups = static_cast<int>(share.size());
    for (Eigen::Index i = 0; i < n; ++i)
      group[static_cast<std::size_t>(i)] = static_cast<int>(data.observations[static_cast<std::size_t>(i)].source);
    return group;
  }
  out.by = HeldOutBy::block;
  out.groups = kBlockFolds;
  std::vector<Eigen::Index> support;
  for (Eigen::Index i = 0; i < n; ++i)
    if (energy[i] > kSupport * largest) support.push_back(i);
  const std::size_t block = std::max<std::size_t>(1, support.size() / (kBlockFolds * kBlocksPerFold));
  for (std::size_t k = 0; k < support.size(); ++k)
    group[static_cast<std::size_t>(support[k])] = static_cast<int>((k / block) % kBlockFolds);
  return group;
}

/// The least-squares coefficients for the normal equations N x = b, in the directions N
/// determines (a group that held all of a coefficient's information leaves it at zero).
Eigen::VectorXd solve(const Eigen::MatrixXd& N, const Eigen::VectorXd& b) {
  const SymmetricEigen eig = symmetric_eigen(N);
  const Eigen::VectorXd& mu = eig.values;
  const double floor = 1e-9 * std::max(mu.maxCoeff(), 0.0);
  Eigen::VectorXd y = eig.vectors.transpose() * b;
  for (Eigen::Index k = 0; k < y.size(); ++k) y[k] = mu[k] > floor && mu[k] > 0 ? y[k] / mu[k] : 0.0;
  return eig.vectors * y;
}

}  // namespace

HeldOut held_out_gain(const Eigen::MatrixXd& columns, const Eigen::VectorXd& r, const MeasurementSet& data) {
  HeldOut out;
  if (columns.rows() == 0 || !(columns.squaredNorm() > 0)) return out;
  const std::vector<int> group = groups_of(columns, data, out);
  const auto k = columns.cols();
  std::vector<Eigen::MatrixXd> N(static_cast<std::size_t>(out.groups), Eigen::MatrixXd::Zero(k, k));
  std::vector<Eigen::VectorXd> b(static_cast<std::size_t>(out.groups), Eigen::VectorXd::Zero(k));
  Eigen::MatrixXd N_all = Eigen::MatrixXd::Zero(k, k);
  Eigen::VectorXd b_all = Eigen::VectorXd::Zero(k);
  for (Eigen::Index i = 0; i < columns.rows(); ++i) {
    const int g = group[static_cast<std::size_t>(i)];
    for (Eigen::Index j = 0; j < k; ++j) {
      const double cr = columns(i, j) * r[i];
      b_all[j] += cr;
      if (g >= 0) b[static_cast<std::size_t>(g)][j] += cr;
      for (Eigen::Index l = 0; l < k; ++l) {
        const double cc = columns(i, j) * columns(i, l);
        N_all(j, l) += cc;
        if (g >= 0) N[static_cast<std::size_t>(g)](j, l) += cc;
      }
    }
  }
  const Eigen::VectorXd x_all = solve(N_all, b_all);
  for (std::size_t g = 0; g < N.size(); ++g) {
    if (!(N[g].trace() > 0)) continue;  // an empty group predicts nothing and is scored on nothing
    const Eigen::VectorXd x = solve(N_all - N[g], b_all - b[g]);
    out.gain += 2.0 * x.dot(b[g]) - x.dot(N[g] * x);
    out.fitted_gain += 2.0 * x_all.dot(b[g]) - x_all.dot(N[g] * x_all);
  }
  return out;
}

}  // namespace ccomp::identify::detail
