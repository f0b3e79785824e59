#pragma once
// The math of multi-head attention of one query over one sample's entities, written once: the
// tape's Attention op (training, a batch of samples, with its backward) and GoalAttention::Apply
// (acting, one sample) both call it. Raw row-major rows: the inner loops run over a head's
// values, contiguous, and vectorize (`#pragma omp simd`); Eigen expressions of 16-value
// segments cost several times their arithmetic here.

#include <cstdint>

namespace srics::nn::attention {

// Where one sample's operands are: the query (embed values), and its entities' keys and values,
// entity e's row at keys + e * row_stride (embed values each); mask: one value per entity (0 =
// absent, skipped) or null for all present.
template <typename T>
struct Sample {
  const T* query = nullptr;
  const T* keys = nullptr;
  const T* values = nullptr;
  int64_t row_stride = 0;
  const T* mask = nullptr;
  int64_t entities = 0;
};

// Per head h (embed / heads values each): scores q_h . k_{e,h} / sqrt(head size), a softmax over
// the present entities into weights[h * entities + e] (0 for absent ones), and
// out_h = sum_e w * v_{e,h}. `out` (embed values) is overwritten; a head with no present entity
// gives zeros.
template <typename T>
void Forward(const Sample<T>& s, int64_t embed, int64_t heads, T* weights, T* out);

// The gradients of Forward's output `grad_out` (embed values) with respect to the query, the keys
// and the values, added to grad_query (embed values), grad_keys and grad_values (rows as keys and
// values, row_stride apart); any of them may be null (not needed). `weights` are Forward's;
// score_grads is the caller's scratch of `entities` values (overwritten).
template <typename T>
void Backward(const Sample<T>& s, int64_t embed, int64_t heads, const T* weights, const T* grad_out, T* grad_query,
              T* grad_keys, T* grad_values, T* score_grads);

extern template void Forward<float>(const Sample<float>&, int64_t, int64_t, float*, float*);
extern template void Forward<double>(const Sample<double>&, int64_t, int64_t, double*, double*);
extern template void Backward<float>(const Sample<float>&, int64_t, int64_t, const float*, const float*, float*, float*,
                                     float*, float*);
extern template void Backward<double>(const Sample<double>&, int64_t, int64_t, const double*, const double*, double*,
                                      double*, double*, double*);

}  // namespace srics::nn::attention
