// ThreadsSeen: which threads took part in TBB's parallel work while it was alive, for tests that claim a result does
// not depend on the thread count: they check that a second thread really ran, not only that the results agree.
// A local task_scheduler_observer of the creating thread's arena: TBB calls on_scheduler_entry on every thread that
// joins the arena, so a worker's id is in the set once parallel work woke it there. Joining is not yet taking a task
// (a worker that finds the work all taken leaves again): what it proves is that the code offered work to a second
// thread, which a serial path never does.
#pragma once
#include <mutex>
#include <set>
#include <thread>

#include <tbb/task_scheduler_observer.h>

namespace wobble::testing {

class ThreadsSeen : public tbb::task_scheduler_observer {
 public:
  ThreadsSeen() : creator_(std::this_thread::get_id()) { observe(true); }
  ~ThreadsSeen() override { observe(false); }

  void on_scheduler_entry(bool) override {
    const std::lock_guard<std::mutex> lock(mutex_);
    ids_.insert(std::this_thread::get_id());
  }
  // Threads other than the creator's that joined the arena.
  int others() const {
    const std::lock_guard<std::mutex> lock(mutex_);
    return int(ids_.size()) - int(ids_.count(creator_));
  }

 private:
  const std::thread::id creator_;
  mutable std::mutex mutex_;
  std::set<std::thread::id> ids_;
};

}  // namespace wobble::testing
