// The libcamera backend's completion queue without a camera: items pushed on one thread come
// out on another in their order, a disconnection wakes a waiting consumer and wins over what
// is queued, and a wait ends at its deadline. Also built under ThreadSanitizer (tests/tsan).
#include <chrono>
#include <thread>

#include <gtest/gtest.h>

#include "capture/libcamera/completion_queue.h"

namespace lumar {
namespace {

using Queue = CompletionQueue<int>;
using namespace std::chrono_literals;

std::chrono::steady_clock::time_point in(std::chrono::steady_clock::duration d)
{
    return std::chrono::steady_clock::now() + d;
}

TEST(CompletionQueue, ItemsCrossThreadsInTheirOrder)
{
    constexpr int kItems = 2000;
    Queue queue;
    std::thread producer([&] {
        for (int i = 0; i < kItems; ++i) {
            queue.push(i);
            if (i % 97 == 0)
                std::this_thread::yield(); // let the consumer find the queue empty now and then
        }
    });
    int item = -1;
    for (int i = 0; i < kItems; ++i) {
        ASSERT_EQ(queue.waitUntil(in(30s), item), Queue::Wait::Item) << "item " << i;
        ASSERT_EQ(item, i);
    }
    producer.join();
    EXPECT_EQ(queue.waitUntil(in(0s), item), Queue::Wait::Timeout);
    EXPECT_EQ(item, kItems - 1) << "a timeout leaves the output alone";
}

TEST(CompletionQueue, ADisconnectionWakesTheConsumerAndWinsOverQueuedItems)
{
    Queue queue;
    queue.push(7);
    int item = -1;
    ASSERT_EQ(queue.waitUntil(in(30s), item), Queue::Wait::Item);
    const auto start = std::chrono::steady_clock::now();
    std::thread producer([&] {
        std::this_thread::sleep_for(20ms);
        queue.push(8);
        queue.disconnect();
    });
    // Woken by the push or the disconnection, long before the deadline; the disconnection
    // wins once it is there, over the queued 8.
    Queue::Wait wait = queue.waitUntil(in(60s), item);
    producer.join();
    if (wait == Queue::Wait::Item) {
        EXPECT_EQ(item, 8);
        wait = queue.waitUntil(in(60s), item);
    }
    EXPECT_EQ(wait, Queue::Wait::Disconnected);
    EXPECT_LT(std::chrono::steady_clock::now() - start, 30s);
    queue.push(9);
    EXPECT_EQ(queue.waitUntil(in(0s), item), Queue::Wait::Disconnected) << "for good";
}

TEST(CompletionQueue, ClearDropsTheItemsNotADisconnection)
{
    Queue queue;
    queue.push(1);
    queue.push(2);
    queue.clear();
    int item = -1;
    EXPECT_EQ(queue.waitUntil(in(10ms), item), Queue::Wait::Timeout);
    queue.disconnect();
    queue.clear();
    EXPECT_EQ(queue.waitUntil(in(0s), item), Queue::Wait::Disconnected);
    EXPECT_EQ(item, -1);
}

} // namespace
} // namespace lumar
