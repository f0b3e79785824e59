#include "common/nn/attention.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>

#if defined(__AVX512F__) || defined(__AVX2__)
#include <immintrin.h>
#endif

namespace srics::nn::attention {

namespace {

// A 16-float dot product with a reduction gcc does not write for `omp simd` (it spills the
// vector and adds its lanes one by one): the paper's head size on the vector units this build
// targets (-march, cmake/SricsOptions.cmake).
#if defined(__AVX512F__)
#define SRICS_ATTENTION_DOT16 1
inline float Dot16(const float* a, const float* b) {
  return _mm512_reduce_add_ps(_mm512_mul_ps(_mm512_loadu_ps(a), _mm512_loadu_ps(b)));
}
#elif defined(__AVX2__) && defined(__FMA__)
#define SRICS_ATTENTION_DOT16 1
inline float Dot16(const float* a, const float* b) {
  const __m256 s = _mm256_fmadd_ps(_mm256_loadu_ps(a + 8), _mm256_loadu_ps(b + 8),
                                   _mm256_mul_ps(_mm256_loadu_ps(a), _mm256_loadu_ps(b)));
  __m128 x = _mm_add_ps(_mm256_castps256_ps128(s), _mm256_extractf128_ps(s, 1));
  x = _mm_add_ps(x, _mm_movehl_ps(x, x));
  x = _mm_add_ss(x, _mm_movehdup_ps(x));
  return _mm_cvtss_f32(x);
}
#endif

// The inner loops run over one head's values. kN > 0 is that length known when compiling (the
// common head sizes, see Forward): the loop then becomes a few whole vector instructions inlined
// into the caller, where a length known only at run time cost a call, a vector loop and its
// remainder per entity and head (about a fifth of a batch-256 run's CPU time on 16-value heads).
template <int kN, typename T>
[[gnu::always_inline]] inline T Dot(const T* a, const T* b, int64_t n) {
#ifdef SRICS_ATTENTION_DOT16
  if constexpr (kN == 16 && std::is_same_v<T, float>) return Dot16(a, b);
#endif
  const int64_t len = kN > 0 ? kN : n;
  T sum = 0;
#pragma omp simd reduction(+ : sum)
  for (int64_t i = 0; i < len; ++i) sum += a[i] * b[i];
  return sum;
}

// y += alpha * x
template <int kN, typename T>
[[gnu::always_inline]] inline void Axpy(T alpha, const T* x, T* y, int64_t n) {
  const int64_t len = kN > 0 ? kN : n;
#pragma omp simd
  for (int64_t i = 0; i < len; ++i) y[i] += alpha * x[i];
}

template <typename T>
bool Present(const Sample<T>& s, int64_t e) {
  return s.mask == nullptr || s.mask[e] != T(0);
}

// kHead: the head size when compiling, 0 = embed / heads at run time.
template <int kHead, typename T>
void ForwardHeads(const Sample<T>& s, int64_t embed, int64_t heads, T* weights, T* out) {
  const int64_t dh = kHead > 0 ? kHead : embed / heads;
  const T scale = T(1) / std::sqrt(static_cast<T>(dh));
  std::fill(out, out + embed, T(0));
  for (int64_t h = 0; h < heads; ++h) {
    const T* q = s.query + h * dh;
    T* w = weights + h * s.entities;
    // scores, then a softmax over the present entities (max subtracted)
    T mx = -std::numeric_limits<T>::infinity();
    for (int64_t e = 0; e < s.entities; ++e) {
      if (!Present(s, e)) continue;
      w[e] = scale * Dot<kHead>(q, s.keys + e * s.row_stride + h * dh, dh);
      mx = std::max(mx, w[e]);
    }
    T sum = 0;
    for (int64_t e = 0; e < s.entities; ++e) {
      w[e] = Present(s, e) ? std::exp(w[e] - mx) : T(0);
      sum += w[e];
    }
    if (sum <= T(0)) continue;
    const T inverse = T(1) / sum;
    T* o = out + h * dh;
    for (int64_t e = 0; e < s.entities; ++e) {
      w[e] *= inverse;
      if (w[e] != T(0)) Axpy<kHead>(w[e], s.values + e * s.row_stride + h * dh, o, dh);
    }
  }
}

template <int kHead, typename T>
void BackwardHeads(const Sample<T>& s, int64_t embed, int64_t heads, const T* weights, const T* grad_out, T* grad_query,
                   T* grad_keys, T* grad_values, T* score_grads) {
  const int64_t dh = kHead > 0 ? kHead : embed / heads;
  const T scale = T(1) / std::sqrt(static_cast<T>(dh));
  T* gs = score_grads;
  for (int64_t h = 0; h < heads; ++h) {
    const T* w = weights + h * s.entities;
    const T* go = grad_out + h * dh;
    // the weights' gradient, then through the softmax to the scores
    T wg = 0;
    for (int64_t e = 0; e < s.entities; ++e) {
      if (w[e] == T(0)) {
        gs[e] = 0;
        continue;
      }
      gs[e] = Dot<kHead>(go, s.values + e * s.row_stride + h * dh, dh);
      wg += w[e] * gs[e];
      if (grad_values) Axpy<kHead>(w[e], go, grad_values + e * s.row_stride + h * dh, dh);
    }
    for (int64_t e = 0; e < s.entities; ++e) {
      if (w[e] == T(0)) continue;
      const T score = scale * w[e] * (gs[e] - wg);
      if (grad_query) Axpy<kHead>(score, s.keys + e * s.row_stride + h * dh, grad_query + h * dh, dh);
      if (grad_keys) Axpy<kHead>(score, s.query + h * dh, grad_keys + e * s.row_stride + h * dh, dh);
    }
  }
}

}  // namespace

// The head sizes compiled in: 16 (the paper's 80 = 5 x 16), 8 and 32; any other runs the same
// code with its size read at run time.
template <typename T>
void Forward(const Sample<T>& s, int64_t embed, int64_t heads, T* weights, T* out) {
  switch (embed / heads) {
    case 16: return ForwardHeads<16>(s, embed, heads, weights, out);
    case 8: return ForwardHeads<8>(s, embed, heads, weights, out);
    case 32: return ForwardHeads<32>(s, embed, heads, weights, out);
    default: return ForwardHeads<0>(s, embed, heads, weights, out);
  }
}

template <typename T>
void Backward(const Sample<T>& s, int64_t embed, int64_t heads, const T* weights, const T* grad_out, T* grad_query,
              T* grad_keys, T* grad_values, T* score_grads) {
  switch (embed / heads) {
    case 16:
      return BackwardHeads<16>(s, embed, heads, weights, grad_out, grad_query, grad_keys, grad_values, score_grads);
    case 8:
      return BackwardHeads<8>(s, embed, heads, weights, grad_out, grad_query, grad_keys, grad_values, score_grads);
    case 32:
      return BackwardHeads<32>(s, embed, heads, weights, grad_out, grad_query, grad_keys, grad_values, score_grads);
    default:
      return BackwardHeads<0>(s, embed, heads, weights, grad_out, grad_query, grad_keys, grad_values, score_grads);
  }
}

template void Forward<float>(const Sample<float>&, int64_t, int64_t, float*, float*);
template void Forward<double>(const Sample<double>&, int64_t, int64_t, double*, double*);
template void Backward<float>(const Sample<float>&, int64_t, int64_t, const float*, const float*, float*, float*,
                              float*, float*);
template void Backward<double>(const Sample<double>&, int64_t, int64_t, const double*, const double*, double*, double*,
                               double*, double*);

}  // namespace srics::nn::attention
