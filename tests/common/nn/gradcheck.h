#pragma once
// Finite-difference gradient checks in double precision for the tape and modules.

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>

#include "common/nn/tape.h"
#include "common/nn/tensor.h"

namespace srics::nn::testing {

using D = double;
using MatD = Matrix<double>;

// Relative error ||a - n|| / (||a|| + ||n|| + 1e-3) between the tape gradient and central
// differences of loss = sum(out * R) (R fixed random weights, so every output element
// matters differently) with respect to every variable. Returns the worst over variables.
// A correct backward gives ~1e-9; any wrong formula gives ~1e-1 or more.
inline double GradCheck(const ParameterList<D>& vars, const std::function<Var<D>(Tape<D>&)>& build, double h = 1e-6) {
  Tape<D> tape;
  Rng rng(123);
  MatD weights;
  auto loss = [&]() {
    tape.Reset();
    Var<D> out = build(tape);
    if (weights.rows() != out.rows() || weights.cols() != out.cols()) {
      weights = RandomNormal<D>(out.rows(), out.cols(), rng);
    }
    return tape.Sum(tape.Mul(out, tape.Constant(weights)));
  };
  ZeroGrad(vars);
  tape.Backward(loss());
  double worst = 0;
  for (Parameter<D>* p : vars) {
    MatD numeric(p->value.rows(), p->value.cols());
    for (Eigen::Index i = 0; i < p->value.size(); ++i) {
      const double x = p->value.data()[i];
      p->value.data()[i] = x + h;
      const double up = loss().value()(0, 0);
      p->value.data()[i] = x - h;
      const double down = loss().value()(0, 0);
      p->value.data()[i] = x;
      numeric.data()[i] = (up - down) / (2 * h);
    }
    // the small floor keeps differencing noise on a truly zero gradient (e.g. the key bias
    // of attention, which cancels in the softmax) from reading as a relative error of 1
    const double err = (p->grad - numeric).norm() / (p->grad.norm() + numeric.norm() + 1e-3);
    worst = std::max(worst, err);
  }
  return worst;
}

// Uniform values in [lo, hi] with a random sign when `signed_values`, keeping every entry at
// least lo away from zero (kinks of relu, clamp and min stay out of the difference step).
inline MatD AwayFromZero(Eigen::Index rows, Eigen::Index cols, Rng& rng, double lo = 0.05, double hi = 1.5,
                         bool signed_values = true) {
  std::uniform_real_distribution<double> u(lo, hi);
  std::bernoulli_distribution s(0.5);
  MatD m(rows, cols);
  for (Eigen::Index i = 0; i < m.size(); ++i) {
    m.data()[i] = u(rng) * (signed_values && s(rng) ? -1.0 : 1.0);
  }
  return m;
}

}  // namespace srics::nn::testing
