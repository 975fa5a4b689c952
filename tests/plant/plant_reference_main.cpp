// plant_reference: the plant core's numbers for an outside tool to check
// (tests/plant/scipy_reference.py compares them with scipy). Reads one plant
// per run on stdin, whitespace separated:
//
//   ss n m p h_ns  A(n*n) B(n*m) C(p*n) D(p*m)  L_ns(m)  steps
//   tf nn nd h_ns  num(nn) den(nd)  L_ns  steps
//
// (matrices row by row, times in integer nanoseconds) and prints, one
// number per token with 17 significant digits:
//
//   Phi (n*n) / Gamma0 (n*m) / Gamma1 (n*m), each on a line, row by row,
//   then `steps` lines "x... | y..." of the state and output after sample
//   k = 1..steps with a unit step on every input from k = 0 (y as
//   linear_plant.hpp defines it: C x[k] + D u[k-1-d]).
//
// Errors (a PlantError) print "error <field>: <message>" and exit 1.
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include "plc/sim/plant/linear_plant.hpp"

namespace pl = plc::plant;

namespace {

pl::Rows read_rows(std::istream& in, int r, int c) {
  pl::Rows m(static_cast<std::size_t>(r), std::vector<double>(static_cast<std::size_t>(c)));
  for (auto& row : m)
    for (auto& v : row) in >> v;
  return m;
}

void print(const Eigen::MatrixXd& m) {
  for (Eigen::Index i = 0; i < m.rows(); ++i)
    for (Eigen::Index j = 0; j < m.cols(); ++j) std::printf("%.17g ", m(i, j));
  std::printf("\n");
}

}  // namespace

int main() {
  std::string kind;
  std::cin >> kind;
  try {
    pl::ContinuousModel model;
    long long h_ns = 0;
    std::vector<plc::TIME> dead;
    if (kind == "ss") {
      int n = 0, m = 0, p = 0;
      std::cin >> n >> m >> p >> h_ns;
      const auto A = read_rows(std::cin, n, n), B = read_rows(std::cin, n, m),
                 C = read_rows(std::cin, p, n), D = read_rows(std::cin, p, m);
      model = pl::state_space(A, B, C, D);
      for (int i = 0; i < m; ++i) {
        long long l = 0;
        std::cin >> l;
        dead.emplace_back(l);
      }
    } else if (kind == "tf") {
      int nn = 0, nd = 0;
      std::cin >> nn >> nd >> h_ns;
      std::vector<double> num(static_cast<std::size_t>(nn)), den(static_cast<std::size_t>(nd));
      for (auto& v : num) std::cin >> v;
      for (auto& v : den) std::cin >> v;
      model = pl::transfer_function(num, den);
      long long l = 0;
      std::cin >> l;
      dead.emplace_back(l);
    } else {
      std::fprintf(stderr, "plant_reference: first token is ss or tf\n");
      return 2;
    }
    int steps = 0;
    std::cin >> steps;
    if (!std::cin) {
      std::fprintf(stderr, "plant_reference: input ended early\n");
      return 2;
    }
    pl::DiscretiseOptions opt;
    opt.dead_time = dead;
    const pl::DiscreteModel d = pl::discretise_zoh(model, plc::TIME(h_ns), opt);
    print(d.Phi);
    print(d.Gamma0);
    print(d.Gamma1);
    pl::LinearPlant plant(d);
    const std::vector<double> u(static_cast<std::size_t>(model.inputs()), 1.0);
    for (int k = 0; k < steps; ++k) {
      plant.step(u);
      for (double x : plant.state()) std::printf("%.17g ", x);
      std::printf("| ");
      for (double y : plant.outputs()) std::printf("%.17g ", y);
      std::printf("\n");
    }
  } catch (const pl::PlantError& e) {
    std::printf("error %s: %s\n", e.field.c_str(), e.what());
    return 1;
  }
  return 0;
}
