#include "fixed_sums.hpp"

#include <algorithm>

#include "ccomp/util/parallel.hpp"

namespace ccomp::identify::detail {
namespace {

constexpr std::size_t kChunks = 8;
constexpr Eigen::Index kBlockRows = 1024;  // rows x F doubles of scratch per thread

/// Candidate c's columns on rows [begin, begin + out.rows()) into `out` (zero off its probe's rows).
void candidate_block(const Candidate& c, const Probe& p, const MeasurementSet& data, Eigen::Index begin,
                     Eigen::Ref<Eigen::MatrixXd> out) {
  const Eigen::Index end = begin + out.rows();
  for (auto it = std::lower_bound(p.rows.begin(), p.rows.end(), begin); it != p.rows.end() && *it < end; ++it) {
    const Observation& o = data.observations[static_cast<std::size_t>(*it)];
    for (int k = 0; k < c.basis_count; ++k) out(*it - begin, k) = p.g[*it] * c.basis(o, k, c.period);
  }
}

FixedSums zero_sums(const std::vector<Candidate>& candidates, const std::vector<Eigen::Index>& column,
                    Eigen::Index m, Eigen::Index F) {
  FixedSums s;
  s.AtC = Eigen::MatrixXd::Zero(m, F);
  s.Ctr = Eigen::VectorXd::Zero(F);
  s.CtC.resize(candidates.size());
  for (std::size_t i = 0; i < candidates.size(); ++i)
    if (column[i] >= 0) s.CtC[i] = Eigen::MatrixXd::Zero(candidates[i].basis_count, candidates[i].basis_count);
  return s;
}

}  // namespace

FixedSums fixed_sums(const std::vector<Candidate>& candidates, const std::vector<Probe>& probes,
                     const std::vector<Eigen::Index>& column, Eigen::Index F, const MeasurementSet& data,
                     const Eigen::MatrixXd& A, const Eigen::VectorXd& r, int threads) {
  const Eigen::Index n = r.size(), m = A.cols();
  std::vector<FixedSums> part(kChunks);
  util::for_each_index(kChunks, threads, [&](std::size_t chunk) {
    const Eigen::Index begin = n * static_cast<Eigen::Index>(chunk) / static_cast<Eigen::Index>(kChunks);
    const Eigen::Index end = n * static_cast<Eigen::Index>(chunk + 1) / static_cast<Eigen::Index>(kChunks);
    FixedSums& s = part[chunk];
    s = zero_sums(candidates, column, m, F);
    Eigen::MatrixXd C(std::min(kBlockRows, std::max<Eigen::Index>(end - begin, 1)), F);
    for (Eigen::Index first = begin; first < end; first += kBlockRows) {
      const Eigen::Index rows = std::min(kBlockRows, end - first);
      auto block = C.topRows(rows);
      block.setZero();
      for (std::size_t i = 0; i < candidates.size(); ++i)
        if (column[i] >= 0)
          candidate_block(candidates[i], probes[candidates[i].probe], data, first,
                          block.middleCols(column[i], candidates[i].basis_count));
      if (m > 0) s.AtC.noalias() += A.middleRows(first, rows).transpose() * block;
      s.Ctr.noalias() += block.transpose() * r.segment(first, rows);
      for (std::size_t i = 0; i < candidates.size(); ++i)
        if (column[i] >= 0) {
          const auto own = block.middleCols(column[i], candidates[i].basis_count);
          s.CtC[i].noalias() += own.transpose() * own;
        }
    }
  });
  FixedSums sum = zero_sums(candidates, column, m, F);
  for (const FixedSums& p : part) {
    sum.AtC += p.AtC, sum.Ctr += p.Ctr;
    for (std::size_t i = 0; i < candidates.size(); ++i)
      if (column[i] >= 0) sum.CtC[i] += p.CtC[i];
  }
  return sum;
}

}  // namespace ccomp::identify::detail
