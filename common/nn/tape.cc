#include "common/nn/tape.h"

#include "common/nn/attention.h"
#include "common/nn/gemm.h"
#include "common/nn/parallel.h"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace srics::nn {
namespace {

using Eigen::Index;

// Query row r of an Attention node's operands with its sample b = r / per_sample (row-major: Q's
// row r, rows b * ents .. of K and V, the mask's row b when there is one).
template <typename T>
attention::Sample<T> SampleOf(const Matrix<T>& Q, const Matrix<T>& K, const Matrix<T>& V, const Matrix<T>* M, Index r,
                              Index per_sample, Index ents) {
  const Index embed = Q.cols(), b = r / per_sample;
  return {Q.data() + r * embed,
          K.data() + b * ents * embed,
          V.data() + b * ents * embed,
          embed,
          M ? M->data() + b * ents : nullptr,
          ents};
}

// The gradient that reaches a row softmax's input z * scale from g, the gradient of its output
// y: scale * y * (g - <g, y>) per row (MaskedSoftmax, GumbelSoftmax).
template <typename T>
Matrix<T> SoftmaxInputGradient(const Matrix<T>& y, const Matrix<T>& g, T scale) {
  const Matrix<T> dot = g.cwiseProduct(y).rowwise().sum();
  return (scale * y.array() * (g.colwise() - dot.col(0)).array()).matrix();
}

// first contribution assigns (no zero fill), later ones add
template <typename NodeT, typename Expr>
void Acc(NodeT& n, const Expr& e) {
  if (!n.has_grad) {
    n.grad = e;
    n.has_grad = true;
  } else {
    n.grad += e;
  }
}

// n.grad (+)= op(l) * op(r): the first contribution assigns, later ones add
template <typename NodeT, typename T>
void AccProduct(NodeT& n, const Matrix<T>& l, bool trans_l, const Matrix<T>& r, bool trans_r) {
  const bool first = !n.has_grad;
  Gemm<T>(trans_l, trans_r, l, r, first ? T(0) : T(1), n.grad);
  n.has_grad = true;
}

// out[c] (+)= g[c] where v[c] > 0, else 0 (+ 0): the relu's gradient from its output v. Eigen
// compares entry by entry; this loop is vectorized (-fopenmp-simd)
template <typename T>
void ReluGradient(const T* v, const T* g, Index n, bool accumulate, T* out) {
  if (accumulate) {
#pragma omp simd
    for (Index c = 0; c < n; ++c) out[c] += v[c] > T(0) ? g[c] : T(0);
  } else {
#pragma omp simd
    for (Index c = 0; c < n; ++c) out[c] = v[c] > T(0) ? g[c] : T(0);
  }
}

// y.row(i) += b.row(0) for every row i. Eigen's y.rowwise() += b runs entry by entry on
// row-major matrices, 3-10x slower than this vectorized loop on the GNN's layer shapes
template <typename T>
void AddToEveryRow(const Matrix<T>& b, Matrix<T>& y) {
  const Index n = y.cols();
  const T* v = b.data();
  for (Index i = 0; i < y.rows(); ++i) {
    T* row = y.data() + i * n;
#pragma omp simd
    for (Index c = 0; c < n; ++c) row[c] += v[c];
  }
}

// makes sure a node's gradient buffer exists (zeroed) before scattered updates
template <typename NodeT>
void EnsureGrad(NodeT& n, Index rows, Index cols) {
  if (!n.has_grad) {
    n.grad.setZero(rows, cols);
    n.has_grad = true;
  }
}

[[noreturn]] void Fail(const char* op, const std::string& what) {
  throw std::invalid_argument(std::string("nn::Tape::") + op + ": " + what);
}

// The message is built only when the check fails: checks run for every op, some for every
// gathered row, and building the string each time cost ~5% of a SAC update at batch 256.
#define SRICS_NN_CHECK(ok, op, what) \
  do {                               \
    if (!(ok)) Fail(op, what);       \
  } while (0)

template <typename M>
std::string Shape(const M& m) {
  return std::to_string(m.rows()) + "x" + std::to_string(m.cols());
}

// a broadcast copy of x at rows x cols (x is rows x cols, 1 x 1, 1 x cols or rows x 1)
template <typename T>
Matrix<T> Expand(const Matrix<T>& x, Index rows, Index cols) {
  if (x.rows() == rows && x.cols() == cols) return x;
  if (x.size() == 1) return Matrix<T>::Constant(rows, cols, x(0, 0));
  if (x.rows() == 1) return x.replicate(rows, 1);
  return x.replicate(1, cols);
}

// sums a full-shape gradient down to a broadcast operand's shape
template <typename T>
Matrix<T> Reduce(const Matrix<T>& g, Index rows, Index cols) {
  if (g.rows() == rows && g.cols() == cols) return g;
  if (rows == 1 && cols == 1) return Matrix<T>::Constant(1, 1, g.sum());
  if (rows == 1) return g.colwise().sum();
  return g.rowwise().sum();
}

bool Broadcastable(Index r, Index c, Index rows, Index cols) { return (r == rows || r == 1) && (c == cols || c == 1); }

// softmax of each row over entries with non-zero mask (mask may be null); rows with no
// valid entry become zero
template <typename T>
void RowSoftmax(const Matrix<T>& x, const Matrix<T>* mask, Matrix<T>& y) {
  y.resize(x.rows(), x.cols());
  for (Index i = 0; i < x.rows(); ++i) {
    T mx = -std::numeric_limits<T>::infinity();
    for (Index j = 0; j < x.cols(); ++j) {
      if (!mask || (*mask)(i, j) != T(0)) mx = std::max(mx, x(i, j));
    }
    T sum = 0;
    for (Index j = 0; j < x.cols(); ++j) {
      const T e = (!mask || (*mask)(i, j) != T(0)) ? std::exp(x(i, j) - mx) : T(0);
      y(i, j) = e;
      sum += e;
    }
    if (sum > T(0)) y.row(i) /= sum;
  }
}

}  // namespace

template <typename T>
void Tape<T>::Reset() {
  count_ = 0;
}

template <typename T>
typename Tape<T>::Node& Tape<T>::NewNode(Op op, BackwardFn backward, int a, int b) {
  if (count_ == static_cast<int>(nodes_.size())) nodes_.emplace_back();
  Node& n = nodes_[count_++];
  n.op = op;
  n.backward = backward;
  n.a = a;
  n.b = b;
  n.c = n.d = -1;
  n.flag = false;
  n.has_grad = false;
  n.param = nullptr;
  n.needs_grad = Needs(a) || Needs(b);
  return n;
}

template <typename T>
const Matrix<T>& Tape<T>::Value(Var<T> v) const {
  return Val(v.id);
}

template <typename T>
const Matrix<T>& Tape<T>::Grad(Var<T> v) {
  Node& n = nodes_[v.id];
  if (n.has_grad) return n.grad;
  const Mat& x = Val(v.id);
  zero_grad_.setZero(x.rows(), x.cols());
  return zero_grad_;
}

template <typename T>
Var<T> Tape<T>::Constant(const Mat& value, bool requires_grad) {
  Node& n = NewNode(Op::kConstant, nullptr);
  n.value = value;
  n.needs_grad = requires_grad;
  return Out(n);
}

template <typename T>
Var<T> Tape<T>::Param(Parameter<T>& p, bool trainable) {
  Node& n = NewNode(Op::kParam, &Tape::BackwardParam);
  n.param = &p;
  n.flag = trainable;
  n.needs_grad = trainable;
  return Out(n);
}

template <typename T>
void Tape<T>::BackwardParam(Node& n) {
  if (!n.flag) return;  // a frozen parameter: its gradient only passes through
  if (gradient_buffer_)
    gradient_buffer_->Add(n.param, n.grad);
  else
    n.param->grad += n.grad;
}

template <typename T>
typename Tape<T>::Node& Tape<T>::Product(Op op, Var<T> a, Var<T> b, const char* what) {
  Node& n = NewNode(op, &Tape::BackwardProduct, a.id, b.id);
  const Mat& A = Val(a.id);
  const Mat& B = Val(b.id);
  SRICS_NN_CHECK(A.cols() == B.rows(), what, Shape(A) + " * " + Shape(B));
  Gemm<T>(false, false, A, B, T(0), n.value);
  LogGemm(A.rows(), A.cols(), B.cols(), false, false);
  return n;
}

template <typename T>
Var<T> Tape<T>::MatMul(Var<T> a, Var<T> b) {
  return Out(Product(Op::kMatMul, a, b, "MatMul"));
}

template <typename T>
Var<T> Tape<T>::Linear(Var<T> x, Var<T> w, Var<T> b) {
  Node& n = Product(Op::kLinear, x, w, "Linear");
  n.c = b.id;
  n.needs_grad = n.needs_grad || Needs(b.id);
  if (b.id >= 0) {
    const Mat& B = Val(b.id);
    SRICS_NN_CHECK(B.rows() == 1 && B.cols() == n.value.cols(), "Linear", "bias " + Shape(B));
    AddToEveryRow(B, n.value);
  }
  return Out(n);
}

// MatMul and Linear: a (m x k) * b (k x n) [+ bias c]
template <typename T>
void Tape<T>::BackwardProduct(Node& n) {
  const Mat& g = n.grad;
  const Mat& A = Val(n.a);
  const Mat& B = Val(n.b);
  if (Needs(n.b)) {
    AccProduct(nodes_[n.b], A, true, g, false);
    LogGemm(A.cols(), A.rows(), g.cols(), true, false);
  }
  if (Needs(n.a)) {
    AccProduct(nodes_[n.a], g, false, B, true);
    LogGemm(g.rows(), g.cols(), B.rows(), false, true);
  }
  const int bias = n.c;
  if (Needs(bias)) Acc(nodes_[bias], g.colwise().sum());
}

template <typename T>
Var<T> Tape<T>::AddBias(Var<T> x, Var<T> b) {
  Node& n = NewNode(Op::kAddBias, &Tape::BackwardAddBias, x.id, b.id);
  const Mat& X = Val(x.id);
  const Mat& B = Val(b.id);
  SRICS_NN_CHECK(B.rows() == 1 && B.cols() == X.cols(), "AddBias", Shape(X) + " + " + Shape(B));
  n.value = X;
  AddToEveryRow(B, n.value);
  return Out(n);
}

template <typename T>
void Tape<T>::BackwardAddBias(Node& n) {
  if (Needs(n.a)) Acc(nodes_[n.a], n.grad);
  if (Needs(n.b)) Acc(nodes_[n.b], n.grad.colwise().sum());
}

template <typename T>
Var<T> Tape<T>::Binary(Op op, Var<T> a, Var<T> b) {
  Node& n = NewNode(op, &Tape::BackwardBinary, a.id, b.id);
  const Mat& A = Val(a.id);
  const Mat& B = Val(b.id);
  const Index rows = std::max(A.rows(), B.rows());
  const Index cols = std::max(A.cols(), B.cols());
  SRICS_NN_CHECK(Broadcastable(A.rows(), A.cols(), rows, cols) && Broadcastable(B.rows(), B.cols(), rows, cols),
                 "elementwise", Shape(A) + " vs " + Shape(B));
  if (op == Op::kMin) {
    SRICS_NN_CHECK(A.rows() == B.rows() && A.cols() == B.cols(), "Min", Shape(A) + " vs " + Shape(B));
  }
  auto compute = [&](const auto& x, const auto& y) {
    switch (op) {
      case Op::kAdd: n.value = x + y; break;
      case Op::kSub: n.value = x - y; break;
      case Op::kMul: n.value = x.cwiseProduct(y); break;
      case Op::kDiv: n.value = x.cwiseQuotient(y); break;
      case Op::kMin: n.value = x.cwiseMin(y); break;
      default: break;
    }
  };
  if (A.rows() == B.rows() && A.cols() == B.cols()) {
    compute(A, B);
  } else {
    compute(Expand(A, rows, cols), Expand(B, rows, cols));
  }
  return Out(n);
}

// Add, Sub, Mul, Div, Min: broadcast operands get their gradient summed down to their shape
template <typename T>
void Tape<T>::BackwardBinary(Node& n) {
  const Mat& g = n.grad;
  const Mat& A = Val(n.a);
  const Mat& B = Val(n.b);
  const bool same = A.rows() == B.rows() && A.cols() == B.cols();
  if (same) {
    switch (n.op) {
      case Op::kAdd:
        if (Needs(n.a)) Acc(nodes_[n.a], g);
        if (Needs(n.b)) Acc(nodes_[n.b], g);
        break;
      case Op::kSub:
        if (Needs(n.a)) Acc(nodes_[n.a], g);
        if (Needs(n.b)) Acc(nodes_[n.b], -g);
        break;
      case Op::kMul:
        if (Needs(n.a)) Acc(nodes_[n.a], g.cwiseProduct(B));
        if (Needs(n.b)) Acc(nodes_[n.b], g.cwiseProduct(A));
        break;
      case Op::kDiv:
        if (Needs(n.a)) Acc(nodes_[n.a], g.cwiseQuotient(B));
        if (Needs(n.b)) {
          Acc(nodes_[n.b], (-g.array() * A.array() / B.array().square()).matrix());
        }
        break;
      case Op::kMin: {
        const auto pick_a = (A.array() <= B.array()).template cast<T>();
        if (Needs(n.a)) Acc(nodes_[n.a], (g.array() * pick_a).matrix());
        if (Needs(n.b)) Acc(nodes_[n.b], (g.array() * (T(1) - pick_a)).matrix());
        break;
      }
      default: break;
    }
    return;
  }
  // broadcasting: work at full shape, then sum down to each operand's shape
  const Mat Af = Expand(A, g.rows(), g.cols());
  const Mat Bf = Expand(B, g.rows(), g.cols());
  Mat ga, gb;
  switch (n.op) {
    case Op::kAdd:
      ga = g;
      gb = g;
      break;
    case Op::kSub:
      ga = g;
      gb = -g;
      break;
    case Op::kMul:
      ga = g.cwiseProduct(Bf);
      gb = g.cwiseProduct(Af);
      break;
    case Op::kDiv:
      ga = g.cwiseQuotient(Bf);
      gb = (-g.array() * Af.array() / Bf.array().square()).matrix();
      break;
    default: break;
  }
  if (Needs(n.a)) Acc(nodes_[n.a], Reduce(ga, A.rows(), A.cols()));
  if (Needs(n.b)) Acc(nodes_[n.b], Reduce(gb, B.rows(), B.cols()));
}

template <typename T>
Var<T> Tape<T>::AddScalar(Var<T> a, T s) {
  Node& n = NewNode(Op::kAddScalar, &Tape::BackwardAddScalar, a.id);
  n.value = Val(a.id).array() + s;
  return Out(n);
}

template <typename T>
void Tape<T>::BackwardAddScalar(Node& n) {
  Acc(nodes_[n.a], n.grad);
}

template <typename T>
Var<T> Tape<T>::MulScalar(Var<T> a, T s) {
  Node& n = NewNode(Op::kMulScalar, &Tape::BackwardMulScalar, a.id);
  n.f0 = s;
  n.value = Val(a.id) * s;
  return Out(n);
}

template <typename T>
void Tape<T>::BackwardMulScalar(Node& n) {
  const T factor = n.f0;
  Acc(nodes_[n.a], n.grad * factor);
}

template <typename T>
Var<T> Tape<T>::Clamp(Var<T> a, T lo, T hi) {
  Node& n = NewNode(Op::kClamp, &Tape::BackwardClamp, a.id);
  n.f0 = lo;
  n.f1 = hi;
  n.value = Val(a.id).cwiseMax(lo).cwiseMin(hi);
  return Out(n);
}

template <typename T>
void Tape<T>::BackwardClamp(Node& n) {
  const T lo = n.f0, hi = n.f1;
  const auto x = Val(n.a).array();
  Acc(nodes_[n.a], (n.grad.array() * ((x >= lo) && (x <= hi)).template cast<T>()).matrix());
}

template <typename T>
Var<T> Tape<T>::Unary(Op op, Var<T> a) {
  Node& n = NewNode(op, &Tape::BackwardUnary, a.id);
  const auto x = Val(a.id).array();
  n.value.resize(x.rows(), x.cols());
  auto y = n.value.array();
  switch (op) {
    case Op::kRelu: y = x.max(T(0)); break;
    case Op::kTanh: y = x.tanh(); break;
    case Op::kSigmoid: y = T(1) / (T(1) + (-x).exp()); break;
    case Op::kExp: y = x.exp(); break;
    case Op::kLog: y = x.log(); break;
    case Op::kSoftplus: y = x.max(T(0)) + (-x.abs()).exp().log1p(); break;
    case Op::kSquare: y = x.square(); break;
    default: break;
  }
  return Out(n);
}

template <typename T>
void Tape<T>::BackwardUnary(Node& n) {
  const Mat& g = n.grad;
  switch (n.op) {
    case Op::kRelu: {
      Node& in = nodes_[n.a];
      if (!in.has_grad) in.grad.resize(g.rows(), g.cols());
      ReluGradient(n.value.data(), g.data(), g.size(), in.has_grad, in.grad.data());
      in.has_grad = true;
      break;
    }
    case Op::kTanh: Acc(nodes_[n.a], (g.array() * (T(1) - n.value.array().square())).matrix()); break;
    case Op::kSigmoid: Acc(nodes_[n.a], (g.array() * n.value.array() * (T(1) - n.value.array())).matrix()); break;
    case Op::kExp: Acc(nodes_[n.a], g.cwiseProduct(n.value)); break;
    case Op::kLog: Acc(nodes_[n.a], g.cwiseQuotient(Val(n.a))); break;
    case Op::kSoftplus: Acc(nodes_[n.a], (g.array() / (T(1) + (-Val(n.a).array()).exp())).matrix()); break;
    case Op::kSquare: Acc(nodes_[n.a], (T(2) * g.array() * Val(n.a).array()).matrix()); break;
    default: break;
  }
}

template <typename T>
Var<T> Tape<T>::Sum(Var<T> a, int axis) {
  SRICS_NN_CHECK(axis >= -1 && axis <= 1, "Sum", "axis " + std::to_string(axis));
  Node& n = NewNode(Op::kSum, &Tape::BackwardSum, a.id);
  n.i0 = axis;
  n.f0 = T(1);
  const Mat& A = Val(a.id);
  if (axis == -1) {
    n.value.resize(1, 1);
    n.value(0, 0) = A.sum();
  } else if (axis == 0) {
    n.value = A.colwise().sum();
  } else {
    n.value = A.rowwise().sum();
  }
  return Out(n);
}

template <typename T>
Var<T> Tape<T>::Mean(Var<T> a, int axis) {
  const Mat& A = Val(a.id);
  const Index count = axis == -1 ? A.size() : axis == 0 ? A.rows() : A.cols();
  Var<T> s = Sum(a, axis);
  Node& n = N(s);
  n.op = Op::kMean;
  n.f0 = T(1) / static_cast<T>(count);
  n.value *= n.f0;
  return s;
}

// Sum and Mean (a Sum node scaled by 1 / count)
template <typename T>
void Tape<T>::BackwardSum(Node& n) {
  const Mat& g = n.grad;
  const Mat& A = Val(n.a);
  const int axis = static_cast<int>(n.i0);
  const T scale = n.f0;
  if (axis == -1) {
    Acc(nodes_[n.a], Mat::Constant(A.rows(), A.cols(), g(0, 0) * scale));
  } else if (axis == 0) {
    Acc(nodes_[n.a], (g * scale).replicate(A.rows(), 1));
  } else {
    Acc(nodes_[n.a], (g * scale).replicate(1, A.cols()));
  }
}

template <typename T>
Var<T> Tape<T>::Concat(const std::vector<Var<T>>& parts, int axis) {
  SRICS_NN_CHECK(!parts.empty(), "Concat", "no parts");
  SRICS_NN_CHECK(axis == 0 || axis == 1, "Concat", "axis " + std::to_string(axis));
  Node& n = NewNode(Op::kConcat, &Tape::BackwardConcat);
  n.i0 = axis;
  n.inputs.clear();
  Index rows = 0, cols = 0;
  for (const Var<T>& p : parts) {
    n.inputs.push_back(p.id);
    n.needs_grad = n.needs_grad || Needs(p.id);
    const Mat& P = Val(p.id);
    if (axis == 1) {
      SRICS_NN_CHECK(cols == 0 || P.rows() == rows, "Concat", "row count " + Shape(P));
      rows = P.rows();
      cols += P.cols();
    } else {
      SRICS_NN_CHECK(rows == 0 || P.cols() == cols, "Concat", "column count " + Shape(P));
      cols = P.cols();
      rows += P.rows();
    }
  }
  n.value.resize(rows, cols);
  Index off = 0;
  for (int id : n.inputs) {
    const Mat& P = Val(id);
    if (axis == 1) {
      n.value.middleCols(off, P.cols()) = P;
      off += P.cols();
    } else {
      n.value.middleRows(off, P.rows()) = P;
      off += P.rows();
    }
  }
  return Out(n);
}

template <typename T>
void Tape<T>::BackwardConcat(Node& n) {
  const Mat& g = n.grad;
  const bool side_by_side = n.i0 == 1;
  Index off = 0;
  for (int in : n.inputs) {
    const Mat& P = Val(in);
    if (side_by_side) {
      if (Needs(in)) Acc(nodes_[in], g.middleCols(off, P.cols()));
      off += P.cols();
    } else {
      if (Needs(in)) Acc(nodes_[in], g.middleRows(off, P.rows()));
      off += P.rows();
    }
  }
}

template <typename T>
Var<T> Tape<T>::Slice(Var<T> a, int axis, Index start, Index length) {
  Node& n = NewNode(Op::kSlice, &Tape::BackwardSlice, a.id);
  const Mat& A = Val(a.id);
  const Index extent = axis == 0 ? A.rows() : A.cols();
  SRICS_NN_CHECK((axis == 0 || axis == 1) && start >= 0 && length >= 0 && start + length <= extent, "Slice",
                 "axis " + std::to_string(axis) + " [" + std::to_string(start) + ", +" + std::to_string(length) +
                     ") of " + Shape(A));
  n.i0 = axis;
  n.i1 = start;
  if (axis == 1) {
    n.value = A.middleCols(start, length);
  } else {
    n.value = A.middleRows(start, length);
  }
  return Out(n);
}

template <typename T>
void Tape<T>::BackwardSlice(Node& n) {
  const Mat& g = n.grad;
  const Mat& A = Val(n.a);
  const int axis = static_cast<int>(n.i0);
  const Index start = n.i1;
  Node& in = nodes_[n.a];
  EnsureGrad(in, A.rows(), A.cols());
  if (axis == 1) {
    in.grad.middleCols(start, g.cols()) += g;
  } else {
    in.grad.middleRows(start, g.rows()) += g;
  }
}

template <typename T>
Var<T> Tape<T>::Reshape(Var<T> a, Index rows, Index cols) {
  Node& n = NewNode(Op::kReshape, &Tape::BackwardReshape, a.id);
  const Mat& A = Val(a.id);
  SRICS_NN_CHECK(rows * cols == A.size(), "Reshape",
                 Shape(A) + " to " + std::to_string(rows) + "x" + std::to_string(cols));
  n.value = Eigen::Map<const Mat>(A.data(), rows, cols);
  return Out(n);
}

template <typename T>
void Tape<T>::BackwardReshape(Node& n) {
  const Mat& A = Val(n.a);
  Acc(nodes_[n.a], Eigen::Map<const Mat>(n.grad.data(), A.rows(), A.cols()));
}

template <typename T>
Var<T> Tape<T>::Transpose(Var<T> a) {
  Node& n = NewNode(Op::kTranspose, &Tape::BackwardTranspose, a.id);
  n.value = Val(a.id).transpose();
  return Out(n);
}

template <typename T>
void Tape<T>::BackwardTranspose(Node& n) {
  Acc(nodes_[n.a], n.grad.transpose());
}

template <typename T>
Var<T> Tape<T>::MaskedSoftmax(Var<T> a, Var<T> mask) {
  Node& n = NewNode(Op::kMaskedSoftmax, &Tape::BackwardMaskedSoftmax, a.id);
  n.c = mask.id;
  const Mat& A = Val(a.id);
  const Mat* M = nullptr;
  if (mask.id >= 0) {
    M = &Val(mask.id);
    SRICS_NN_CHECK(M->rows() == A.rows() && M->cols() == A.cols(), "MaskedSoftmax",
                   "mask " + Shape(*M) + " for " + Shape(A));
  }
  RowSoftmax(A, M, n.value);
  return Out(n);
}

template <typename T>
void Tape<T>::BackwardMaskedSoftmax(Node& n) {
  Acc(nodes_[n.a], SoftmaxInputGradient(n.value, n.grad, T(1)));
}

template <typename T>
Var<T> Tape<T>::LogSoftmax(Var<T> a) {
  Node& n = NewNode(Op::kLogSoftmax, &Tape::BackwardLogSoftmax, a.id);
  const Mat& A = Val(a.id);
  RowSoftmax<T>(A, nullptr, n.aux);
  n.value.resize(A.rows(), A.cols());
  for (Index i = 0; i < A.rows(); ++i) {
    const T mx = A.row(i).maxCoeff();
    const T lse = mx + std::log((A.row(i).array() - mx).exp().sum());
    n.value.row(i) = A.row(i).array() - lse;
  }
  return Out(n);
}

template <typename T>
void Tape<T>::BackwardLogSoftmax(Node& n) {
  const Mat& g = n.grad;
  const Mat& softmax = n.aux;
  const auto total = g.rowwise().sum();
  Acc(nodes_[n.a], (g.array() - softmax.array().colwise() * total.array()).matrix());
}

template <typename T>
Var<T> Tape<T>::GumbelSoftmax(Var<T> logits, const Mat& gumbel_noise, T temperature, bool hard) {
  Node& n = NewNode(Op::kGumbelSoftmax, &Tape::BackwardGumbelSoftmax, logits.id);
  const Mat& L = Val(logits.id);
  SRICS_NN_CHECK(gumbel_noise.rows() == L.rows() && gumbel_noise.cols() == L.cols(), "GumbelSoftmax",
                 "noise " + Shape(gumbel_noise) + " for " + Shape(L));
  SRICS_NN_CHECK(temperature > T(0), "GumbelSoftmax", "temperature must be positive");
  n.f0 = temperature;
  n.flag = hard;
  Mat z = (L + gumbel_noise) / temperature;
  RowSoftmax<T>(z, nullptr, n.aux);
  if (hard) {
    n.value.setZero(L.rows(), L.cols());
    for (Index i = 0; i < L.rows(); ++i) {
      Index j;
      n.aux.row(i).maxCoeff(&j);
      n.value(i, j) = T(1);
    }
  } else {
    n.value = n.aux;
  }
  return Out(n);
}

template <typename T>
void Tape<T>::BackwardGumbelSoftmax(Node& n) {
  // straight-through: the gradient of the soft sample (n.aux), whatever the forward returned;
  // its input was the logits over the temperature
  Acc(nodes_[n.a], SoftmaxInputGradient(n.aux, n.grad, T(1) / n.f0));
}

template <typename T>
Var<T> Tape<T>::Gather(Var<T> a, const std::vector<int>& index) {
  Node& n = NewNode(Op::kGather, &Tape::BackwardGather, a.id);
  const Mat& A = Val(a.id);
  n.index = index;
  n.value.resize(static_cast<Index>(index.size()), A.cols());
  for (size_t i = 0; i < index.size(); ++i) {
    SRICS_NN_CHECK(index[i] >= 0 && index[i] < A.rows(), "Gather",
                   "index " + std::to_string(index[i]) + " of " + Shape(A));
    n.value.row(i) = A.row(index[i]);
  }
  return Out(n);
}

template <typename T>
void Tape<T>::BackwardGather(Node& n) {
  const Mat& A = Val(n.a);
  Node& in = nodes_[n.a];
  EnsureGrad(in, A.rows(), A.cols());
  for (size_t i = 0; i < n.index.size(); ++i) in.grad.row(n.index[i]) += n.grad.row(i);
}

template <typename T>
Var<T> Tape<T>::ScatterAdd(Var<T> a, const std::vector<int>& index, Index num_rows, Var<T> weight) {
  Node& n = NewNode(Op::kScatterAdd, &Tape::BackwardScatterAdd, a.id, weight.id);
  const Mat& A = Val(a.id);
  SRICS_NN_CHECK(static_cast<Index>(index.size()) == A.rows(), "ScatterAdd",
                 std::to_string(index.size()) + " indices for " + Shape(A));
  const Mat* W = weight.id >= 0 ? &Val(weight.id) : nullptr;
  SRICS_NN_CHECK(!W || (W->rows() == A.rows() && W->cols() == 1), "ScatterAdd",
                 "weight " + Shape(*W) + " for " + Shape(A));
  n.index = index;
  n.value.setZero(num_rows, A.cols());
  for (size_t i = 0; i < index.size(); ++i) {
    SRICS_NN_CHECK(index[i] >= 0 && index[i] < num_rows, "ScatterAdd",
                   "index " + std::to_string(index[i]) + " of " + std::to_string(num_rows));
    if (W)
      n.value.row(index[i]) += (*W)(i, 0) * A.row(i);
    else
      n.value.row(index[i]) += A.row(i);
  }
  return Out(n);
}

template <typename T>
void Tape<T>::BackwardScatterAdd(Node& n) {
  const Mat& g = n.grad;
  const Mat& A = Val(n.a);
  const int weight = n.b;
  const Mat* W = weight >= 0 ? &Val(weight) : nullptr;
  if (Needs(n.a)) {
    Node& in = nodes_[n.a];
    EnsureGrad(in, A.rows(), A.cols());
    for (size_t i = 0; i < n.index.size(); ++i) {
      if (W)
        in.grad.row(i) += (*W)(i, 0) * g.row(n.index[i]);
      else
        in.grad.row(i) += g.row(n.index[i]);
    }
  }
  if (Needs(weight)) {
    Node& w = nodes_[weight];
    EnsureGrad(w, A.rows(), 1);
    for (size_t i = 0; i < n.index.size(); ++i) w.grad(i, 0) += g.row(n.index[i]).dot(A.row(i));
  }
}

template <typename T>
Var<T> Tape<T>::GatherSumRelu(Var<T> a, const std::vector<int>& a_index, Var<T> b, const std::vector<int>& b_index,
                              Index col, Index width) {
  Node& n = NewNode(Op::kGatherSumRelu, &Tape::BackwardGatherSumRelu, a.id, b.id);
  const Mat& A = Val(a.id);
  const Mat& B = Val(b.id);
  if (width < 0) width = A.cols() - col;
  SRICS_NN_CHECK(
      A.cols() == B.cols() && a_index.size() == b_index.size() && col >= 0 && col + width <= A.cols(), "GatherSumRelu",
      "columns " + std::to_string(col) + " +" + std::to_string(width) + " of " + Shape(A) + " and " + Shape(B) +
          " with " + std::to_string(a_index.size()) + " and " + std::to_string(b_index.size()) + " indices");
  n.index = a_index;
  n.index_b = b_index;
  n.i0 = col;
  n.value.resize(static_cast<Index>(a_index.size()), width);
  for (size_t i = 0; i < a_index.size(); ++i) {
    SRICS_NN_CHECK(a_index[i] >= 0 && a_index[i] < A.rows() && b_index[i] >= 0 && b_index[i] < B.rows(),
                   "GatherSumRelu",
                   "indices " + std::to_string(a_index[i]) + ", " + std::to_string(b_index[i]) + " of " + Shape(A) +
                       ", " + Shape(B));
    n.value.row(i) = (A.row(a_index[i]).segment(col, width) + B.row(b_index[i]).segment(col, width)).cwiseMax(T(0));
  }
  return Out(n);
}

template <typename T>
void Tape<T>::BackwardGatherSumRelu(Node& n) {
  const Mat& g = n.grad;
  const Mat& A = Val(n.a);
  const Mat& B = Val(n.b);
  const Index col = n.i0;
  const bool na = Needs(n.a), nb = Needs(n.b);
  if (na) EnsureGrad(nodes_[n.a], A.rows(), A.cols());
  if (nb) EnsureGrad(nodes_[n.b], B.rows(), B.cols());
  for (size_t i = 0; i < n.index.size(); ++i) {
    // the relu's gradient of this pair, added to both of its rows
    const T* v = n.value.row(i).data();
    const T* gi = g.row(i).data();
    if (na) ReluGradient(v, gi, g.cols(), true, &nodes_[n.a].grad(n.index[i], col));
    if (nb) ReluGradient(v, gi, g.cols(), true, &nodes_[n.b].grad(n.index_b[i], col));
  }
}

template <typename T>
Var<T> Tape<T>::Attention(Var<T> q, Var<T> k, Var<T> v, Var<T> mask, int num_heads, int queries_per_sample) {
  Node& n = NewNode(Op::kAttention, &Tape::BackwardAttention, q.id, k.id);
  n.c = v.id;
  n.d = mask.id;
  n.i0 = num_heads;
  n.i1 = queries_per_sample;
  n.needs_grad = n.needs_grad || Needs(v.id);
  const Mat& Q = Val(q.id);
  const Mat& K = Val(k.id);
  const Mat& V = Val(v.id);
  const Index queries = Q.rows(), embed = Q.cols(), per_sample = queries_per_sample;
  SRICS_NN_CHECK(num_heads > 0 && embed % num_heads == 0, "Attention",
                 std::to_string(embed) + " not divisible into " + std::to_string(num_heads) + " heads");
  SRICS_NN_CHECK(per_sample > 0 && queries > 0 && queries % per_sample == 0, "Attention",
                 "q " + Shape(Q) + " with " + std::to_string(per_sample) + " queries per sample");
  const Index batch = queries / per_sample;
  SRICS_NN_CHECK(K.rows() % batch == 0 && K.cols() == embed && V.rows() == K.rows() && V.cols() == embed, "Attention",
                 "q " + Shape(Q) + " k " + Shape(K) + " v " + Shape(V));
  const Index ents = K.rows() / batch;
  const Mat* M = nullptr;
  if (mask.id >= 0) {
    M = &Val(mask.id);
    SRICS_NN_CHECK(M->rows() == batch && M->cols() == ents, "Attention", "mask " + Shape(*M));
  }
  n.aux.resize(queries, num_heads * ents);
  n.value.resize(queries, embed);
  for (Index r = 0; r < queries; ++r)
    attention::Forward(SampleOf(Q, K, V, M, r, per_sample, ents), embed, num_heads, n.aux.data() + r * n.aux.cols(),
                       n.value.data() + r * embed);
  return Out(n);
}

template <typename T>
void Tape<T>::BackwardAttention(Node& n) {
  const Mat& g = n.grad;
  const Mat& Q = Val(n.a);
  const Mat& K = Val(n.b);
  const Mat& V = Val(n.c);
  const Index queries = Q.rows(), embed = Q.cols(), heads = n.i0, per_sample = n.i1;
  const Index ents = K.rows() / (queries / per_sample);
  const bool nq = Needs(n.a), nk = Needs(n.b), nv = Needs(n.c);
  if (nq) EnsureGrad(nodes_[n.a], queries, embed);
  if (nk) EnsureGrad(nodes_[n.b], K.rows(), embed);
  if (nv) EnsureGrad(nodes_[n.c], V.rows(), embed);
  T* gq = nq ? nodes_[n.a].grad.data() : nullptr;
  T* gk = nk ? nodes_[n.b].grad.data() : nullptr;
  T* gv = nv ? nodes_[n.c].grad.data() : nullptr;
  // the mask is in the weights (0 for an absent entity); the queries of one sample add into
  // its keys' and values' gradients
  std::vector<T> score_grads(static_cast<size_t>(ents));
  for (Index r = 0; r < queries; ++r) {
    const Index b = r / per_sample;
    attention::Backward(SampleOf<T>(Q, K, V, nullptr, r, per_sample, ents), embed, heads,
                        n.aux.data() + r * n.aux.cols(), g.data() + r * embed, gq ? gq + r * embed : nullptr,
                        gk ? gk + b * ents * embed : nullptr, gv ? gv + b * ents * embed : nullptr, score_grads.data());
  }
}

template <typename T>
const Matrix<T>& Tape<T>::AttentionWeights(Var<T> attention) const {
  const Node& n = N(attention);
  SRICS_NN_CHECK(n.op == Op::kAttention, "AttentionWeights", "not an Attention node");
  return n.aux;
}

template <typename T>
void Tape<T>::Backward(Var<T> loss) {
  SRICS_NN_CHECK(Val(loss.id).size() == 1, "Backward", "loss must be 1x1, is " + Shape(Val(loss.id)));
  Backward(loss, Mat::Ones(1, 1));
}

template <typename T>
void Tape<T>::Backward(Var<T> out, const Mat& seed) {
  SRICS_NN_CHECK(out.tape == this && out.id >= 0 && out.id < count_, "Backward", "foreign variable");
  SRICS_NN_CHECK(seed.rows() == Val(out.id).rows() && seed.cols() == Val(out.id).cols(), "Backward",
                 "seed " + Shape(seed) + " for " + Shape(Val(out.id)));
  for (int i = 0; i < count_; ++i) nodes_[i].has_grad = false;
  Node& o = nodes_[out.id];
  o.grad = seed;
  o.has_grad = true;
  for (int id = out.id; id >= 0; --id) {
    Node& n = nodes_[id];
    if (n.has_grad && n.needs_grad && n.backward) (this->*n.backward)(n);
  }
}

template class Tape<float>;
template class Tape<double>;

}  // namespace srics::nn
