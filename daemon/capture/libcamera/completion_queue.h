// The hand-over from libcamera's thread to the capture thread: requests complete into a queue
// in their order, the camera's disconnection is a flag that wins over what is still queued,
// and the capture thread waits for either until a deadline. A template without libcamera so
// that its threads can be tested (and run under ThreadSanitizer, tests/tsan) without a camera.
#pragma once

#include <chrono>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <utility>

namespace lumar {

template <typename T> class CompletionQueue {
public:
    enum class Wait { Item, Timeout, Disconnected };

    // Called on the producer's (libcamera's) thread.
    void push(T item)
    {
        {
            const std::lock_guard lock(mutex_);
            items_.push_back(std::move(item));
        }
        changed_.notify_one();
    }
    void disconnect()
    {
        {
            const std::lock_guard lock(mutex_);
            disconnected_ = true;
        }
        changed_.notify_one();
    }

    // Waits until `deadline` at most. Item: `out` is the oldest item, taken off the queue.
    // Disconnected as soon as the producer said so, whatever is still queued (the camera is
    // gone: its queued requests are no frames to hand on).
    Wait waitUntil(std::chrono::steady_clock::time_point deadline, T& out)
    {
        std::unique_lock lock(mutex_);
        changed_.wait_until(lock, deadline, [this] { return disconnected_ || !items_.empty(); });
        if (disconnected_)
            return Wait::Disconnected;
        if (items_.empty())
            return Wait::Timeout;
        out = std::move(items_.front());
        items_.pop_front();
        return Wait::Item;
    }

    // Drops what is queued (the producer is stopped); a disconnection stays.
    void clear()
    {
        const std::lock_guard lock(mutex_);
        items_.clear();
    }

private:
    std::mutex mutex_;
    std::condition_variable changed_;
    std::deque<T> items_;
    bool disconnected_ = false;
};

} // namespace lumar
