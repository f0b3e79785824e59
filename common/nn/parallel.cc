#include "common/nn/parallel.h"

#include <Eigen/Core>

namespace srics::nn {

WorkerPool::WorkerPool(int threads) {
  if (threads < 1) throw std::invalid_argument("nn::WorkerPool: threads must be >= 1, is " + std::to_string(threads));
  Eigen::initParallel();
  errors_.resize(static_cast<size_t>(threads));
  workers_.reserve(static_cast<size_t>(threads - 1));
  for (int part = 1; part < threads; ++part) workers_.emplace_back([this, part] { Loop(part); });
}

WorkerPool::~WorkerPool() {
  {
    std::lock_guard<std::mutex> lock(mu_);
    stop_ = true;
  }
  start_cv_.notify_all();
  for (std::thread& t : workers_) t.join();
}

void WorkerPool::Run(const std::function<void(int)>& job) {
  if (workers_.empty()) {
    job(0);
    return;
  }
  {
    std::lock_guard<std::mutex> lock(mu_);
    job_ = &job;
    pending_ = static_cast<int>(workers_.size());
    for (auto& e : errors_) e = nullptr;
    ++generation_;
  }
  start_cv_.notify_all();
  try {
    job(0);
  } catch (...) {
    errors_[0] = std::current_exception();
  }
  {
    std::unique_lock<std::mutex> lock(mu_);
    done_cv_.wait(lock, [this] { return pending_ == 0; });
    job_ = nullptr;
  }
  for (const auto& e : errors_)
    if (e) std::rethrow_exception(e);
}

void WorkerPool::Loop(int part) {
  uint64_t seen = 0;
  for (;;) {
    const std::function<void(int)>* job;
    {
      std::unique_lock<std::mutex> lock(mu_);
      start_cv_.wait(lock, [&] { return stop_ || generation_ != seen; });
      if (stop_) return;
      seen = generation_;
      job = job_;
    }
    std::exception_ptr error;
    try {
      (*job)(part);
    } catch (...) {
      error = std::current_exception();
    }
    {
      std::lock_guard<std::mutex> lock(mu_);
      errors_[static_cast<size_t>(part)] = error;
      if (--pending_ == 0) done_cv_.notify_one();
    }
  }
}

}  // namespace srics::nn
