#pragma once
// The eigen-decomposition of a symmetric matrix (a normal matrix A^T A, a projected one), in
// one place: the identification's files share one instantiation of Eigen's solver.
#include <Eigen/Core>

namespace ccomp::identify {

struct SymmetricEigen {
  Eigen::VectorXd values;   ///< in ascending order
  Eigen::MatrixXd vectors;  ///< column k: the unit eigenvector of values[k]
};

/// The eigenvalues and eigenvectors of the symmetric matrix N (its lower triangle is read).
[[nodiscard]] SymmetricEigen symmetric_eigen(const Eigen::MatrixXd& N);

}  // namespace ccomp::identify
