#include "pipescope/util/work_queue.h"

#include <gtest/gtest.h>

#include <thread>
#include <vector>

namespace pipescope {
namespace {

TEST(WorkQueueTest, ConsumerReceivesEveryItemInOrderThenTheEnd) {
  WorkQueue<int> queue;
  std::vector<int> received;
  std::thread consumer([&] {
    while (std::optional<int> item = queue.Pop()) received.push_back(*item);
  });
  for (int i = 0; i < 1000; ++i) queue.Push(i);
  queue.Close();
  consumer.join();
  ASSERT_EQ(received.size(), 1000u);
  for (int i = 0; i < 1000; ++i) EXPECT_EQ(received[i], i);
}

TEST(WorkQueueTest, ItemsPushedBeforeCloseAreStillDelivered) {
  WorkQueue<int> queue;
  queue.Push(1);
  queue.Push(2);
  queue.Close();
  EXPECT_EQ(queue.Pop(), 1);
  EXPECT_EQ(queue.Pop(), 2);
  EXPECT_FALSE(queue.Pop().has_value());
}

}  // namespace
}  // namespace pipescope
