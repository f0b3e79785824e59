#pragma once
// Running one computation on several threads with the same result up to summation order:
// a fixed pool of worker threads (WorkerPool) and per-thread gradient buffers
// (GradientBuffer) that a tape fills instead of Parameter::grad, added in a fixed order
// afterwards, so results are deterministic for a given thread count.
//
//   nn::WorkerPool pool(2);
//   nn::GradientBuffer<float> shard1(params);   // for the tape of part 1
//   tape1.set_gradient_buffer(&shard1);
//   pool.Run([&](int part) { /* forward + Backward on part's rows, tape of `part` */ });
//   shard1.AddInto();                           // params' grad += part 1's gradients

#include <algorithm>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <functional>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <unordered_map>
#include <utility>
#include <vector>

#include "common/nn/tensor.h"

namespace srics::nn {

// A fixed set of threads that run one job of size() parts at a time: Run(job) calls job(0)
// on the calling thread and job(k) on worker k (k = 1 .. size()-1), and returns when every
// part is done; an exception thrown by a part is rethrown by Run (the lowest part's first).
// Threads start in the constructor and are joined by the destructor. Run is not reentrant
// and belongs to one calling thread.
class WorkerPool {
 public:
  // threads >= 1 (1: no worker, Run calls job(0) inline).
  explicit WorkerPool(int threads);
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  int size() const { return static_cast<int>(workers_.size()) + 1; }
  void Run(const std::function<void(int)>& job);

 private:
  void Loop(int part);

  std::mutex mu_;
  std::condition_variable start_cv_, done_cv_;
  const std::function<void(int)>* job_ = nullptr;
  uint64_t generation_ = 0;
  int pending_ = 0;
  bool stop_ = false;
  std::vector<std::exception_ptr> errors_;
  std::vector<std::thread> workers_;
};

// One gradient buffer per parameter of a list. A tape with set_gradient_buffer(&buffer)
// accumulates trainable parameters' gradients here instead of in Parameter::grad, so tapes
// on several threads can run Backward over the same parameters at once. AddInto adds what
// was accumulated into Parameter::grad (list order) and empties the buffer.
template <typename T>
class GradientBuffer {
 public:
  explicit GradientBuffer(const ParameterList<T>& params)
      : params_(params), grads_(params.size()), touched_(params.size(), false) {
    for (size_t i = 0; i < params_.size(); ++i) index_[params_[i]] = i;
  }

  // grad(p) += g (the first contribution after AddInto assigns). Throws std::invalid_argument
  // for a parameter that is not in the list.
  void Add(const Parameter<T>* p, const Matrix<T>& g) {
    const auto it = index_.find(p);
    if (it == index_.end())
      throw std::invalid_argument("nn::GradientBuffer: parameter " + p->name + " is not in the buffer's list");
    const size_t i = it->second;
    if (touched_[i]) {
      grads_[i] += g;
    } else {
      grads_[i] = g;
      touched_[i] = true;
    }
  }

  // Parameter::grad += this buffer, for every parameter that received a gradient; then empty.
  void AddInto() {
    for (size_t i = 0; i < params_.size(); ++i) {
      if (!touched_[i]) continue;
      params_[i]->grad += grads_[i];
      touched_[i] = false;
    }
  }

  // Forgets what was accumulated.
  void Clear() { std::fill(touched_.begin(), touched_.end(), false); }

 private:
  ParameterList<T> params_;
  std::vector<Matrix<T>> grads_;
  std::vector<bool> touched_;
  std::unordered_map<const Parameter<T>*, size_t> index_;
};

// Rows [begin, end) of part `part` when `rows` rows are split into `parts` near-equal parts.
inline std::pair<int, int> PartRows(int rows, int parts, int part) {
  const int64_t begin = static_cast<int64_t>(rows) * part / parts;
  const int64_t end = static_cast<int64_t>(rows) * (part + 1) / parts;
  return {static_cast<int>(begin), static_cast<int>(end)};
}

}  // namespace srics::nn
