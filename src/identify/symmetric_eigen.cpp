#include "symmetric_eigen.hpp"

#include <Eigen/Eigenvalues>

namespace ccomp::identify {

SymmetricEigen symmetric_eigen(const Eigen::MatrixXd& N) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(N);
  return {solver.eigenvalues(), solver.eigenvectors()};
}

}  // namespace ccomp::identify
