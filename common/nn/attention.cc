#include "common/nn/attention.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace srics::nn::attention {

namespace {

template <typename T>
T Dot(const T* a, const T* b, int64_t n) {
  T sum = 0;
#pragma omp simd reduction(+ : sum)
  for (int64_t i = 0; i < n; ++i) sum += a[i] * b[i];
  return sum;
}

// y += alpha * x
template <typename T>
void Axpy(T alpha, const T* x, T* y, int64_t n) {
#pragma omp simd
  for (int64_t i = 0; i < n; ++i) y[i] += alpha * x[i];
}

template <typename T>
bool Present(const Sample<T>& s, int64_t e) {
  return s.mask == nullptr || s.mask[e] != T(0);
}

}  // namespace

template <typename T>
void Forward(const Sample<T>& s, int64_t embed, int64_t heads, T* weights, T* out) {
  const int64_t dh = embed / heads;
  const T scale = T(1) / std::sqrt(static_cast<T>(dh));
  std::fill(out, out + embed, T(0));
  for (int64_t h = 0; h < heads; ++h) {
    const T* q = s.query + h * dh;
    T* w = weights + h * s.entities;
    // scores, then a softmax over the present entities (max subtracted)
    T mx = -std::numeric_limits<T>::infinity();
    for (int64_t e = 0; e < s.entities; ++e) {
      if (!Present(s, e)) continue;
      w[e] = scale * Dot(q, s.keys + e * s.row_stride + h * dh, dh);
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
      if (w[e] != T(0)) Axpy(w[e], s.values + e * s.row_stride + h * dh, o, dh);
    }
  }
}

template <typename T>
void Backward(const Sample<T>& s, int64_t embed, int64_t heads, const T* weights, const T* grad_out, T* grad_query,
              T* grad_keys, T* grad_values, T* score_grads) {
  const int64_t dh = embed / heads;
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
      gs[e] = Dot(go, s.values + e * s.row_stride + h * dh, dh);
      wg += w[e] * gs[e];
      if (grad_values) Axpy(w[e], go, grad_values + e * s.row_stride + h * dh, dh);
    }
    for (int64_t e = 0; e < s.entities; ++e) {
      if (w[e] == T(0)) continue;
      const T score = scale * w[e] * (gs[e] - wg);
      if (grad_query) Axpy(score, s.keys + e * s.row_stride + h * dh, grad_query + h * dh, dh);
      if (grad_keys) Axpy(score, s.query + h * dh, grad_keys + e * s.row_stride + h * dh, dh);
    }
  }
}

template void Forward<float>(const Sample<float>&, int64_t, int64_t, float*, float*);
template void Forward<double>(const Sample<double>&, int64_t, int64_t, double*, double*);
template void Backward<float>(const Sample<float>&, int64_t, int64_t, const float*, const float*, float*, float*,
                              float*, float*);
template void Backward<double>(const Sample<double>&, int64_t, int64_t, const double*, const double*, double*, double*,
                               double*, double*);

}  // namespace srics::nn::attention
