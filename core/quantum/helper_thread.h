// A second thread for work that splits into independent parts (the 3D fate report's chunks).
// Internal to core/quantum. Started at the first use, ended with its owner; between uses it
// waits on a condition variable, so a running match allocates nothing for it.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <thread>

namespace quantum::detail {

class HelperThread {
 public:
  HelperThread() = default;
  HelperThread(const HelperThread&) = delete;
  HelperThread& operator=(const HelperThread&) = delete;
  ~HelperThread() {
    if (!thread_.joinable()) return;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      quit_ = true;
    }
    wake_.notify_all();
    thread_.join();
  }

  // Calls job(context) on the helper thread and on this one at once, and returns when both calls
  // have returned. The job shares its work out itself (e.g. by an atomic counter) and must not throw.
  void together(void (*job)(void*), void* context) {
    if (!thread_.joinable()) thread_ = std::thread([this] { serve(); });
    {
      std::lock_guard<std::mutex> lock(mutex_);
      job_ = job, context_ = context;
      ++posted_;
    }
    wake_.notify_all();
    job(context);
    std::unique_lock<std::mutex> lock(mutex_);
    wake_.wait(lock, [&] { return finished_ == posted_; });
  }

 private:
  void serve() {
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
      wake_.wait(lock, [&] { return quit_ || finished_ != posted_; });
      if (quit_) return;
      void (*job)(void*) = job_;
      void* context = context_;
      lock.unlock();
      job(context);
      lock.lock();
      finished_ = posted_;
      wake_.notify_all();
    }
  }

  std::thread thread_;
  std::mutex mutex_;
  std::condition_variable wake_;
  void (*job_)(void*) = nullptr;
  void* context_ = nullptr;
  uint64_t posted_ = 0, finished_ = 0;  // jobs handed to the helper, and done by it
  bool quit_ = false;
};

}  // namespace quantum::detail
