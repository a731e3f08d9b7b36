// status.json's latency percentiles: nearest rank over the latest frames only.
#include <gtest/gtest.h>

#include "latency_window.h"

namespace lumar {
namespace {

TEST(LatencyWindow, EmptyUntilTheFirstFrame)
{
    const LatencyWindow window(4);
    EXPECT_FALSE(window.percentile(0.5));
}

TEST(LatencyWindow, PercentilesOfTheLatestFramesInOrder)
{
    LatencyWindow window(5);
    for (double ms : {50.0, 10.0, 40.0, 20.0, 30.0})
        window.add(ms);
    EXPECT_EQ(window.size(), 5u);
    EXPECT_EQ(*window.percentile(0.0), 10.0);
    EXPECT_EQ(*window.percentile(0.5), 30.0);
    EXPECT_EQ(*window.percentile(0.99), 50.0);
    // Two newer frames push out the two oldest (50 and 10).
    window.add(35.0);
    window.add(36.0);
    EXPECT_EQ(window.size(), 5u);
    EXPECT_EQ(*window.percentile(0.0), 20.0);
    EXPECT_EQ(*window.percentile(0.5), 35.0);
    EXPECT_EQ(*window.percentile(1.0), 40.0);
    EXPECT_LE(*window.percentile(0.5), *window.percentile(0.99));
}

} // namespace
} // namespace lumar
