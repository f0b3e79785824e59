#pragma once
// Reverse-mode automatic differentiation over whole-matrix operations.
//
// A Tape records each operation of a forward pass as one node holding its output; Backward
// walks the nodes in reverse and accumulates gradients into the inputs and into the
// Parameter::grad of every trainable parameter used. Reset() forgets the nodes but keeps their
// buffers, so a training loop that builds the same graph each iteration stops allocating after
// the first one. Single-threaded: a tape belongs to one thread; several tapes may read the same
// parameters at once when each writes its gradients to its own GradientBuffer.

#include <cstdint>
#include <vector>

#include "common/nn/tensor.h"

namespace srics::nn {

template <typename T>
class Tape;
template <typename T>
class GradientBuffer;  // common/nn/parallel.h

// A handle to one node of a tape: cheap to copy, valid until the tape's next Reset().
template <typename T>
struct Var {
  Tape<T>* tape = nullptr;
  int id = -1;

  // The node's forward value.
  const Matrix<T>& value() const { return tape->Value(*this); }
  // The node's gradient after Backward (zero matrix of the value's shape if none reached it).
  const Matrix<T>& grad() const { return tape->Grad(*this); }
  Eigen::Index rows() const { return value().rows(); }
  Eigen::Index cols() const { return value().cols(); }
};

// Shape of one matrix product C(m x n) = op(A) op(B) with inner size k, as recorded for the
// benchmark's "GEMM floor". transpose_a / transpose_b tell which operand was transposed.
struct GemmShape {
  Eigen::Index m, k, n;
  bool transpose_a, transpose_b;
};

// The operations a node can hold.
enum class Op : std::uint8_t {
  kConstant,
  kParam,
  kMatMul,
  kLinear,
  kAddBias,
  kAdd,
  kSub,
  kMul,
  kDiv,
  kAddScalar,
  kMulScalar,
  kRelu,
  kTanh,
  kSigmoid,
  kExp,
  kLog,
  kSoftplus,
  kSquare,
  kSum,
  kMean,
  kConcat,
  kSlice,
  kReshape,
  kTranspose,
  kMaskedSoftmax,
  kLogSoftmax,
  kMin,
  kClamp,
  kGumbelSoftmax,
  kGather,
  kScatterAdd,
  kAttention,
  kGatherSumRelu,
};

template <typename T>
class Tape {
 public:
  using Mat = Matrix<T>;

  Tape() = default;
  Tape(const Tape&) = delete;
  Tape& operator=(const Tape&) = delete;

  // Forgets all nodes; their buffers are kept for reuse by the next forward pass.
  void Reset();
  // Number of nodes recorded since the last Reset.
  int size() const { return count_; }

  // Leaves.
  // A constant input (copied into the tape); no gradient is computed for it unless
  // requires_grad is true (used by gradient checks on inputs).
  Var<T> Constant(const Mat& value, bool requires_grad = false);
  // A parameter; when trainable, Backward adds its gradient into p.grad. A frozen parameter
  // (trainable = false) still passes gradients through to other inputs (e.g. a critic used
  // in the policy loss).
  Var<T> Param(Parameter<T>& p, bool trainable = true);

  // Linear algebra.
  Var<T> MatMul(Var<T> a, Var<T> b);            // a (m x k) * b (k x n)
  Var<T> Linear(Var<T> x, Var<T> w, Var<T> b);  // x w + b, b is 1 x n (b.id < 0: none)
  Var<T> AddBias(Var<T> x, Var<T> b);           // x + b broadcast over rows, b is 1 x n

  // Elementwise arithmetic. Either operand may broadcast: shape 1 x 1, 1 x n or m x 1.
  Var<T> Add(Var<T> a, Var<T> b) { return Binary(Op::kAdd, a, b); }
  Var<T> Sub(Var<T> a, Var<T> b) { return Binary(Op::kSub, a, b); }
  Var<T> Mul(Var<T> a, Var<T> b) { return Binary(Op::kMul, a, b); }
  Var<T> Div(Var<T> a, Var<T> b) { return Binary(Op::kDiv, a, b); }
  Var<T> AddScalar(Var<T> a, T s);
  Var<T> MulScalar(Var<T> a, T s);
  // same shapes; ties send the gradient to a
  Var<T> Min(Var<T> a, Var<T> b) { return Binary(Op::kMin, a, b); }
  Var<T> Clamp(Var<T> a, T lo, T hi);  // zero gradient outside [lo, hi]

  // Elementwise functions.
  Var<T> Relu(Var<T> a) { return Unary(Op::kRelu, a); }
  Var<T> Tanh(Var<T> a) { return Unary(Op::kTanh, a); }
  Var<T> Sigmoid(Var<T> a) { return Unary(Op::kSigmoid, a); }
  Var<T> Exp(Var<T> a) { return Unary(Op::kExp, a); }
  Var<T> Log(Var<T> a) { return Unary(Op::kLog, a); }
  Var<T> Softplus(Var<T> a) { return Unary(Op::kSoftplus, a); }  // log(1 + e^a), overflow-safe
  Var<T> Square(Var<T> a) { return Unary(Op::kSquare, a); }

  // Reductions. axis -1: all elements (1 x 1); 0: over rows (1 x n); 1: over columns (m x 1).
  Var<T> Sum(Var<T> a, int axis = -1);
  Var<T> Mean(Var<T> a, int axis = -1);

  // Shapes.
  Var<T> Concat(const std::vector<Var<T>>& parts, int axis = 1);  // 1: side by side
  Var<T> Slice(Var<T> a, int axis, Eigen::Index start, Eigen::Index length);
  Var<T> Reshape(Var<T> a, Eigen::Index rows, Eigen::Index cols);  // row-major order kept
  Var<T> Transpose(Var<T> a);

  // Softmax along each row over the entries whose mask is non-zero; masked entries are 0.
  // mask must be a node of a's shape (usually a Constant); pass mask.id < 0 for no mask.
  Var<T> MaskedSoftmax(Var<T> a, Var<T> mask);
  Var<T> Softmax(Var<T> a) { return MaskedSoftmax(a, Var<T>{this, -1}); }
  Var<T> LogSoftmax(Var<T> a);  // along rows, no mask

  // Gumbel-softmax along rows with the given Gumbel noise (same shape as logits) and
  // temperature. hard = true returns the one-hot argmax in the forward pass while the
  // gradient is that of the soft sample (straight-through estimator).
  Var<T> GumbelSoftmax(Var<T> logits, const Mat& gumbel_noise, T temperature, bool hard);

  // out.row(i) = a.row(index[i]); gradients scatter-add back.
  Var<T> Gather(Var<T> a, const std::vector<int>& index);
  // out (num_rows x n) with out.row(index[i]) += a.row(i), times weight(i, 0) when a
  // weight (a.rows() x 1) is given; gradients gather back.
  Var<T> ScatterAdd(Var<T> a, const std::vector<int>& index, Eigen::Index num_rows, Var<T> weight = {});
  // out.row(i) = relu(a.row(a_index[i]) + b.row(b_index[i])) over the columns col ..
  // col + width - 1 (width < 0: all): a first layer on pairs of rows (graph edges) from its
  // per-row halves in one pass, without pair-sized temporaries; gradients scatter-add back.
  Var<T> GatherSumRelu(Var<T> a, const std::vector<int>& a_index, Var<T> b, const std::vector<int>& b_index,
                       Eigen::Index col = 0, Eigen::Index width = -1);

  // Multi-head attention of Q queries per sample over that sample's entities.
  // q: (B*Q) x E, row b*Q + j holding query j of sample b; k, v: (B*N) x E with row b*N + n
  // holding entity n of sample b; mask: B x N (non-zero = real entity, a Constant) or
  // mask.id < 0 for none. E splits into num_heads heads of E / num_heads; scores are scaled by
  // 1/sqrt(head size). Returns (B*Q) x E: per query and head the softmax-weighted sum of its
  // sample's values. The weights are kept (AttentionWeights).
  Var<T> Attention(Var<T> q, Var<T> k, Var<T> v, Var<T> mask, int num_heads, int queries_per_sample = 1);
  // The (B*Q) x (num_heads*N) attention weights of an Attention node (row b*Q + j, column h*N + n).
  const Mat& AttentionWeights(Var<T> attention) const;

  // Backpropagates from a 1 x 1 node with seed 1.
  void Backward(Var<T> loss);
  // Backpropagates from any node with an explicit seed gradient of its shape.
  void Backward(Var<T> out, const Mat& seed);

  // Access used by Var.
  const Mat& Value(Var<T> v) const;
  const Mat& Grad(Var<T> v);

  // When set, every matrix product executed (forward and backward) appends its shape here.
  void set_gemm_log(std::vector<GemmShape>* log) { gemm_log_ = log; }
  // When set, Backward accumulates trainable parameters' gradients into `buffer` instead of
  // Parameter::grad (tapes on several threads over the same parameters; common/nn/parallel.h).
  void set_gradient_buffer(GradientBuffer<T>* buffer) { gradient_buffer_ = buffer; }

 private:
  struct Node;
  // An op's backward: adds the gradient of its output (n.grad) into its inputs' gradients. Each
  // op names its own when it records the node; tape.cc defines it right after the op's forward.
  using BackwardFn = void (Tape::*)(Node& n);

  // One recorded op. The inputs and settings sit in generic slots; each op's forward and
  // backward name what it keeps where (e.g. Slice: i0 the axis, i1 the start).
  struct Node {
    Op op = Op::kConstant;
    BackwardFn backward = nullptr;  // null: a constant, nothing to pass on
    bool needs_grad = false;
    bool has_grad = false;
    bool flag = false;  // op-specific: trainable, hard
    int a = -1, b = -1, c = -1, d = -1;
    Eigen::Index i0 = 0, i1 = 0;
    T f0 = 0, f1 = 0;
    std::vector<int> inputs;   // concat parts
    std::vector<int> index;    // gather / scatter
    std::vector<int> index_b;  // second index of GatherSumRelu
    Parameter<T>* param = nullptr;
    Mat value, grad, aux;
  };

  Node& NewNode(Op op, BackwardFn backward, int a = -1, int b = -1);
  Var<T> Out(const Node& n) { return Var<T>{this, static_cast<int>(&n - nodes_.data())}; }
  Node& N(Var<T> v) { return nodes_[v.id]; }
  const Node& N(Var<T> v) const { return nodes_[v.id]; }
  const Mat& Val(int id) const {
    const Node& n = nodes_[id];
    return n.op == Op::kParam ? n.param->value : n.value;
  }
  bool Needs(int id) const { return id >= 0 && nodes_[id].needs_grad; }
  Var<T> Binary(Op op, Var<T> a, Var<T> b);
  // a new node holding a * b (checked shapes; `what` names the op in errors)
  Node& Product(Op op, Var<T> a, Var<T> b, const char* what);
  Var<T> Unary(Op op, Var<T> a);
  // the ops' backwards, in the order of their forwards
  void BackwardParam(Node& n);
  void BackwardProduct(Node& n);  // MatMul, Linear
  void BackwardAddBias(Node& n);
  void BackwardBinary(Node& n);  // Add, Sub, Mul, Div, Min
  void BackwardAddScalar(Node& n);
  void BackwardMulScalar(Node& n);
  void BackwardClamp(Node& n);
  void BackwardUnary(Node& n);  // Relu, Tanh, Sigmoid, Exp, Log, Softplus, Square
  void BackwardSum(Node& n);    // Sum, Mean
  void BackwardConcat(Node& n);
  void BackwardSlice(Node& n);
  void BackwardReshape(Node& n);
  void BackwardTranspose(Node& n);
  void BackwardMaskedSoftmax(Node& n);
  void BackwardLogSoftmax(Node& n);
  void BackwardGumbelSoftmax(Node& n);
  void BackwardGather(Node& n);
  void BackwardScatterAdd(Node& n);
  void BackwardGatherSumRelu(Node& n);
  void BackwardAttention(Node& n);
  void LogGemm(Eigen::Index m, Eigen::Index k, Eigen::Index n, bool ta, bool tb) {
    if (gemm_log_) gemm_log_->push_back({m, k, n, ta, tb});
  }

  std::vector<Node> nodes_;
  int count_ = 0;
  std::vector<GemmShape>* gemm_log_ = nullptr;
  GradientBuffer<T>* gradient_buffer_ = nullptr;
  Mat zero_grad_;
};

extern template class Tape<float>;
extern template class Tape<double>;

}  // namespace srics::nn
