#include "robot_agent/agent/outbox.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <filesystem>
#include <fstream>

#include "robot_agent/agent/backoff.h"
#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

using ::testing::HasSubstr;

class OutboxTest : public ::testing::Test {
 protected:
  std::unique_ptr<Outbox> Open() {
    std::string error;
    auto outbox = Outbox::Open(path_, &error);
    EXPECT_NE(outbox, nullptr) << error;
    return outbox;
  }
  static OutboxKey Submap(int64_t id, int64_t revision) {
    return {"r1", OutboxKind::kSubmap, id, revision};
  }
  static bool Put(Outbox* outbox, const OutboxKey& key, const std::string& payload, double now,
                  bool supersede = false) {
    bool inserted = false;
    std::string error;
    EXPECT_TRUE(outbox->Enqueue(key, payload, now, supersede, &inserted, &error)) << error;
    return inserted;
  }
  static std::vector<OutboxItem> Due(Outbox* outbox, OutboxKind kind, double now, int limit = 100,
                                     int64_t bytes = 1 << 30) {
    std::vector<OutboxItem> items;
    std::string error;
    EXPECT_TRUE(outbox->Due(kind, now, limit, bytes, &items, &error)) << error;
    return items;
  }
  static OutboxCounts Counts(Outbox* outbox) {
    OutboxCounts counts;
    std::string error;
    EXPECT_TRUE(outbox->Counts(&counts, &error)) << error;
    return counts;
  }
  const testing::ScopedTempDir dir_{"outbox"};
  const std::string path_ = dir_.path() + "/outbox.db";
};

TEST_F(OutboxTest, PersistsAcrossReopenInInsertionOrder) {
  {
    auto outbox = Open();
    EXPECT_TRUE(Put(outbox.get(), Submap(0, 1), "a", 100.0));
    EXPECT_TRUE(Put(outbox.get(), Submap(1, 1), "b", 100.0));
    EXPECT_TRUE(Put(outbox.get(), {"r1", OutboxKind::kTrajectory, 0, 7}, "t", 100.0));
  }
  auto outbox = Open();
  const auto items = Due(outbox.get(), OutboxKind::kSubmap, 100.0);
  ASSERT_EQ(items.size(), 2u);
  EXPECT_EQ(items[0].payload, "a");
  EXPECT_EQ(items[1].payload, "b");
  EXPECT_EQ(items[1].key.id, 1);
  EXPECT_EQ(items[1].key.revision, 1);
  const OutboxCounts counts = Counts(outbox.get());
  EXPECT_EQ(counts.pending, 3);
  EXPECT_EQ(counts.pending_submaps, 2);
  EXPECT_EQ(counts.pending_trajectories, 1);
}

TEST_F(OutboxTest, AcknowledgeRemovesOnlyThoseItems) {
  auto outbox = Open();
  Put(outbox.get(), Submap(0, 1), "a", 0.0);
  Put(outbox.get(), Submap(1, 1), "b", 0.0);
  const auto items = Due(outbox.get(), OutboxKind::kSubmap, 0.0);
  std::string error;
  ASSERT_TRUE(outbox->Acknowledge({items[0].seq}, &error)) << error;
  const auto left = Due(outbox.get(), OutboxKind::kSubmap, 0.0);
  ASSERT_EQ(left.size(), 1u);
  EXPECT_EQ(left[0].payload, "b");
  // Acknowledging an unknown or already removed item is harmless.
  EXPECT_TRUE(outbox->Acknowledge({items[0].seq, 9999}, &error)) << error;
  outbox.reset();
  EXPECT_EQ(Counts(Open().get()).pending, 1);
}

TEST_F(OutboxTest, SameNaturalKeyIsQueuedOnce) {
  auto outbox = Open();
  EXPECT_TRUE(Put(outbox.get(), Submap(3, 2), "first", 0.0));
  EXPECT_FALSE(Put(outbox.get(), Submap(3, 2), "second", 0.0));
  EXPECT_TRUE(Put(outbox.get(), Submap(3, 3), "newer", 0.0));
  // Same id and revision for another robot or kind is another item.
  EXPECT_TRUE(Put(outbox.get(), {"r2", OutboxKind::kSubmap, 3, 2}, "other robot", 0.0));
  EXPECT_TRUE(Put(outbox.get(), {"r1", OutboxKind::kDetection, 3, 2}, "detection", 0.0));
  const auto items = Due(outbox.get(), OutboxKind::kSubmap, 0.0);
  ASSERT_EQ(items.size(), 3u);
  EXPECT_EQ(items[0].payload, "first");
}

TEST_F(OutboxTest, SupersedeDropsOlderRevisionsOfTheSameItem) {
  auto outbox = Open();
  Put(outbox.get(), Submap(0, 1), "s0r1", 0.0, true);
  Put(outbox.get(), Submap(1, 1), "s1r1", 0.0, true);
  Put(outbox.get(), Submap(0, 2), "s0r2", 0.0, true);
  const auto items = Due(outbox.get(), OutboxKind::kSubmap, 0.0);
  ASSERT_EQ(items.size(), 2u);
  EXPECT_EQ(items[0].payload, "s1r1");
  EXPECT_EQ(items[1].payload, "s0r2");
  // An older revision arriving late is superseded on arrival.
  EXPECT_FALSE(Put(outbox.get(), Submap(1, 0), "s1r0", 0.0, true));
  EXPECT_EQ(Due(outbox.get(), OutboxKind::kSubmap, 0.0).size(), 2u);
  // Without supersede every revision is kept.
  EXPECT_TRUE(Put(outbox.get(), Submap(1, 0), "s1r0", 0.0, false));
  EXPECT_EQ(Due(outbox.get(), OutboxKind::kSubmap, 0.0).size(), 3u);
}

TEST_F(OutboxTest, FailuresFollowTheBackoffSchedule) {
  auto outbox = Open();
  Put(outbox.get(), Submap(0, 1), "a", 10.0);
  BackoffOptions backoff;
  backoff.initial = 1.0;
  backoff.multiplier = 2.0;
  backoff.max = 5.0;
  backoff.jitter = 0.0;
  double now = 10.0;
  const double expected_delays[] = {1.0, 2.0, 4.0, 5.0, 5.0};
  for (int attempt = 1; attempt <= 5; ++attempt) {
    auto items = Due(outbox.get(), OutboxKind::kSubmap, now);
    ASSERT_EQ(items.size(), 1u) << "attempt " << attempt;
    EXPECT_EQ(items[0].attempts, attempt - 1);
    const double delay = BackoffDelay(backoff, items[0].attempts + 1, 0.5);
    EXPECT_DOUBLE_EQ(delay, expected_delays[attempt - 1]);
    std::string error;
    ASSERT_TRUE(outbox->RecordFailure(items[0].seq, now + delay, "down", &error)) << error;
    EXPECT_TRUE(Due(outbox.get(), OutboxKind::kSubmap, now + delay - 0.01).empty());
    double next = 0.0;
    ASSERT_TRUE(outbox->NextDueTime(&next, &error));
    EXPECT_DOUBLE_EQ(next, now + delay);
    now += delay;
  }
  const auto items = Due(outbox.get(), OutboxKind::kSubmap, now);
  ASSERT_EQ(items.size(), 1u);
  EXPECT_EQ(items[0].attempts, 5);
  EXPECT_EQ(items[0].last_error, "down");
  // After a restart everything is due again.
  std::string error;
  ASSERT_TRUE(outbox->RecordFailure(items[0].seq, now + 100.0, "down", &error));
  ASSERT_TRUE(outbox->MakeAllDue(now, &error));
  EXPECT_EQ(Due(outbox.get(), OutboxKind::kSubmap, now).size(), 1u);
}

TEST_F(OutboxTest, DueRespectsLimitAndBytes) {
  auto outbox = Open();
  for (int i = 0; i < 10; ++i) Put(outbox.get(), Submap(i, 0), std::string(100, 'x'), 0.0);
  EXPECT_EQ(Due(outbox.get(), OutboxKind::kSubmap, 0.0, 4).size(), 4u);
  EXPECT_EQ(Due(outbox.get(), OutboxKind::kSubmap, 0.0, 100, 350).size(), 3u);
  // An item larger than the byte budget still goes, alone.
  EXPECT_EQ(Due(outbox.get(), OutboxKind::kSubmap, 0.0, 100, 10).size(), 1u);
  EXPECT_TRUE(Due(outbox.get(), OutboxKind::kDetection, 0.0).empty());
}

TEST_F(OutboxTest, RejectMovesTheItemAside) {
  auto outbox = Open();
  Put(outbox.get(), Submap(0, 1), "bad", 0.0);
  const auto items = Due(outbox.get(), OutboxKind::kSubmap, 0.0);
  std::string error;
  ASSERT_TRUE(outbox->Reject(items[0].seq, 3, "malformed grid", &error)) << error;
  EXPECT_TRUE(Due(outbox.get(), OutboxKind::kSubmap, 0.0).empty());
  const OutboxCounts counts = Counts(outbox.get());
  EXPECT_EQ(counts.pending, 0);
  EXPECT_EQ(counts.rejected, 1);
  std::vector<OutboxItem> rejected;
  ASSERT_TRUE(outbox->Rejected(&rejected, &error));
  ASSERT_EQ(rejected.size(), 1u);
  EXPECT_EQ(rejected[0].payload, "bad");
  EXPECT_EQ(rejected[0].last_error, "malformed grid");
}

TEST_F(OutboxTest, BinaryPayloadsSurviveIntact) {
  auto outbox = Open();
  std::string payload;
  for (int i = 0; i < 256; ++i) payload.push_back(static_cast<char>(i));
  Put(outbox.get(), Submap(0, 0), payload, 0.0);
  outbox.reset();
  outbox = Open();
  EXPECT_EQ(Due(outbox.get(), OutboxKind::kSubmap, 0.0)[0].payload, payload);
}

TEST_F(OutboxTest, NotADatabaseIsAClearError) {
  std::ofstream(path_) << "this is a text file, not SQLite, and long enough to have a header "
                          "that SQLite will read and refuse.......................\n";
  std::string error;
  EXPECT_EQ(Outbox::Open(path_, &error), nullptr);
  EXPECT_THAT(error, HasSubstr(path_));
  EXPECT_THAT(error, HasSubstr("not a usable SQLite database"));
}

TEST_F(OutboxTest, CorruptDatabaseIsAClearError) {
  {
    auto outbox = Open();
    for (int i = 0; i < 200; ++i) Put(outbox.get(), Submap(i, 0), std::string(2000, 'p'), 0.0);
  }
  // Keep SQLite's header, scribble over the pages behind it.
  {
    std::fstream file(path_, std::ios::in | std::ios::out | std::ios::binary);
    file.seekp(4096 + 100);
    const std::string junk(20000, '\x5a');
    file.write(junk.data(), static_cast<std::streamsize>(junk.size()));
  }
  std::string error;
  EXPECT_EQ(Outbox::Open(path_, &error), nullptr);
  EXPECT_THAT(error, HasSubstr(path_));
  EXPECT_THAT(error, ::testing::AnyOf(HasSubstr("corrupt"), HasSubstr("not a usable")));
}

TEST_F(OutboxTest, NewerSchemaIsRefused) {
  Open().reset();
  // A newer agent bumped the schema version.
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path_.c_str(), &db), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(db, "PRAGMA user_version=99", nullptr, nullptr, nullptr), SQLITE_OK);
  sqlite3_close(db);
  std::string error;
  EXPECT_EQ(Outbox::Open(path_, &error), nullptr);
  EXPECT_THAT(error, HasSubstr("schema version 99"));
}

TEST_F(OutboxTest, UnwritablePathIsAClearError) {
  std::string error;
  EXPECT_EQ(Outbox::Open("/nonexistent-dir/x/outbox.db", &error), nullptr);
  EXPECT_THAT(error, HasSubstr("/nonexistent-dir/x/outbox.db"));
}

TEST(BackoffTest, GrowsThenCapsWithJitterBelowTheCap) {
  BackoffOptions options;
  options.initial = 0.5;
  options.multiplier = 3.0;
  options.max = 10.0;
  options.jitter = 0.25;
  EXPECT_DOUBLE_EQ(BackoffDelay(options, 1, 0.0), 0.5);
  EXPECT_DOUBLE_EQ(BackoffDelay(options, 2, 0.0), 1.5);
  EXPECT_DOUBLE_EQ(BackoffDelay(options, 3, 0.0), 4.5);
  EXPECT_DOUBLE_EQ(BackoffDelay(options, 4, 0.0), 10.0);
  EXPECT_DOUBLE_EQ(BackoffDelay(options, 1000000, 0.0), 10.0);
  // Jitter shortens by up to 25 %.
  EXPECT_DOUBLE_EQ(BackoffDelay(options, 1, 1.0), 0.375);
  EXPECT_DOUBLE_EQ(BackoffDelay(options, 4, 0.5), 8.75);
  for (double u : {0.0, 0.3, 0.999}) {
    EXPECT_LE(BackoffDelay(options, 50, u), options.max);
    EXPECT_GE(BackoffDelay(options, 50, u), 0.0);
  }
}

}  // namespace
}  // namespace fleetmap
