#pragma once
// Dense backend of the BLCP core: A stored in full, A_FF gathered and factored by Eigen's blocked
// Cholesky (LLT) for every new free set. For islands up to SolverParams::dense_max_rows rows and
// for the small interface problems of the substructured solver (DESIGN.md §7).
#include "solve/blcp.hpp"

#include <Eigen/Cholesky>

#include <optional>

namespace rbpart {

class DenseBlcpMatrix final : public BlcpMatrix {
 public:
  // Takes A (symmetric, both triangles filled, positive diagonal).
  void assign(Eigen::MatrixXd a);
  // Lets the caller fill A in place: resize(n), fill matrix(), then finalize().
  void resize(int n);
  Eigen::MatrixXd& matrix() { return a_; }
  void finalize();

  int size() const override { return static_cast<int>(a_.rows()); }
  const Eigen::VectorXd& diagonal() const override { return diag_; }
  void multiply(const Eigen::VectorXd& x, Eigen::VectorXd& y) override;
  void solve(Eigen::VectorXd& x) override;

 protected:
  bool factor(const std::vector<char>& free) override;
  bool factor_shifted(const std::vector<char>& free, const Eigen::VectorXd& shift) override;

 private:
  Eigen::MatrixXd a_;
  Eigen::VectorXd diag_;
  Eigen::MatrixXd l_;        // n x n buffer; its leading |F| x |F| block holds the factor of A_FF
  Eigen::VectorXd rhs_;      // gathered right-hand side
  std::vector<int> index_;   // free rows in increasing order
  std::optional<Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>>> llt_;
  bool factor_gathered(const std::vector<char>& free, const Eigen::VectorXd* shift);
};

}  // namespace rbpart
