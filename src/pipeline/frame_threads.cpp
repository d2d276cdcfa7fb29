#include "pipeline/frame_threads.h"

#include <algorithm>
#include <condition_variable>
#include <deque>
#include <exception>
#include <mutex>
#include <optional>
#include <thread>

#include "io/clip_writer.h"
#include "util/error.h"
#include "util/interrupt.h"
#include "util/progress.h"

namespace pluvia {
namespace {

// A small blocking queue with a capacity, so the reader stays at most a few frames ahead.
template <typename T>
class BoundedQueue {
 public:
  explicit BoundedQueue(size_t capacity) : capacity_(capacity) {}
  void push(T item) {
    std::unique_lock lock(mutex_);
    notFull_.wait(lock, [&] { return items_.size() < capacity_ || closed_; });
    if (closed_) return;
    items_.push_back(std::move(item));
    notEmpty_.notify_one();
  }
  std::optional<T> pop() {
    std::unique_lock lock(mutex_);
    notEmpty_.wait(lock, [&] { return !items_.empty() || closed_; });
    if (items_.empty()) return std::nullopt;
    T item = std::move(items_.front());
    items_.pop_front();
    notFull_.notify_one();
    return item;
  }
  void close() {
    std::lock_guard lock(mutex_);
    closed_ = true;
    notEmpty_.notify_all();
    notFull_.notify_all();
  }

 private:
  size_t capacity_;
  std::deque<T> items_;
  bool closed_ = false;
  std::mutex mutex_;
  std::condition_variable notEmpty_, notFull_;
};

// The first error from any thread wins; the others stop when they see it.
class ErrorSlot {
 public:
  void set(std::exception_ptr e) {
    std::lock_guard lock(mutex_);
    if (!error_) error_ = e;
  }
  bool isSet() {
    std::lock_guard lock(mutex_);
    return error_ != nullptr;
  }
  void rethrow() {
    std::lock_guard lock(mutex_);
    if (error_) std::rethrow_exception(error_);
  }

 private:
  std::mutex mutex_;
  std::exception_ptr error_;
};

}  // namespace

int renderFrames(RenderSession& session, const RenderRequest& request,
                 const std::vector<int64_t>& frames, StageTimes& times) {
  auto writer = openClipWriter(request.output, session.clip().width, session.clip().height,
                               session.writerOptions());
  ErrorSlot error;
  BoundedQueue<FrameContext> decoded(3);
  BoundedQueue<FrameContext> finished(std::max(2, 2 * request.threads));
  Progress progress(int(frames.size()), request.progress);

  std::thread readerThread([&] {
    try {
      for (int64_t f : frames) {
        if (error.isSet()) break;
        throwIfInterrupted();
        decoded.push(session.readFrame(f));
      }
    } catch (...) {
      error.set(std::current_exception());
    }
    decoded.close();
  });

  const int writerCount = writer->isMovie() ? 1 : std::max(1, request.threads);
  std::vector<std::thread> writerThreads;
  std::mutex countMutex;
  int framesWritten = 0;
  for (int w = 0; w < writerCount; ++w) {
    writerThreads.emplace_back([&] {
      while (auto frame = finished.pop()) {
        if (error.isSet()) continue;  // drain
        try {
          ScopedTimer timer(&times, "encode");
          writer->write(frame->frame, frame->image);
          std::lock_guard lock(countMutex);
          ++framesWritten;
        } catch (const Error& e) {
          error.set(
              std::make_exception_ptr(Error(e.what(), {"write", frame->frame, e.context().file})));
        } catch (...) {
          error.set(std::current_exception());
        }
        progress.step();
      }
    });
  }

  try {
    while (auto frame = decoded.pop()) {
      if (error.isSet()) break;
      throwIfInterrupted();
      session.processFrame(*frame);
      {
        ScopedTimer timer(&times, "colour out");
        session.toOutput(frame->image);
      }
      finished.push(std::move(*frame));
    }
  } catch (...) {
    error.set(std::current_exception());
  }
  decoded.close();
  finished.close();
  readerThread.join();
  for (auto& t : writerThreads) t.join();
  progress.finish();
  error.rethrow();
  {
    ScopedTimer timer(&times, "encode");
    writer->close();
  }
  return framesWritten;
}

}  // namespace pluvia
