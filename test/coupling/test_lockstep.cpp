#include <gtest/gtest.h>

#include "coupling/lockstep.hpp"

using coupling::Follower;
using coupling::Leader;
using coupling::ProtocolError;

TEST(Lockstep, LeaderAndFollowerAdvanceTogether) {
  Leader l;
  Follower f;
  for (int k = 0; k < 100; ++k) {
    auto s = l.request(k * 0.01);
    EXPECT_EQ(s, static_cast<std::uint64_t>(k));
    EXPECT_EQ(f.on_request(s), Follower::Action::Advance);
    f.answered(s);
    EXPECT_TRUE(l.answer(s, k * 0.01 + 0.001));
  }
  EXPECT_EQ(l.completed(), 100u);
  EXPECT_EQ(f.advanced(), 100u);
  EXPECT_EQ(l.duplicates(), 0u);
}

TEST(Lockstep, LateFollowerGetsResentFirstRequest) {
  Leader l({30.0, 0.5, 120.0});
  auto s = l.request(0.0);
  EXPECT_FALSE(l.should_resend(0.2));
  EXPECT_TRUE(l.should_resend(0.6));   // follower not up yet: resend
  EXPECT_FALSE(l.should_resend(0.7));
  Follower f;  // starts now, sees the resent step 0
  EXPECT_EQ(f.on_request(s), Follower::Action::Advance);
  f.answered(s);
  EXPECT_TRUE(l.answer(s, 0.8));
}

TEST(Lockstep, RepeatedRequestIsAnsweredFromCacheNotAdvancedTwice) {
  Follower f;
  EXPECT_EQ(f.on_request(0), Follower::Action::Advance);
  f.answered(0);
  EXPECT_EQ(f.on_request(0), Follower::Action::Resend);
  EXPECT_EQ(f.on_request(1), Follower::Action::Advance);
  f.answered(1);
  EXPECT_EQ(f.on_request(0), Follower::Action::Ignore);
  EXPECT_EQ(f.advanced(), 2u);
}

TEST(Lockstep, DuplicateAnswerCountedNotApplied) {
  Leader l;
  auto s0 = l.request(0);
  EXPECT_TRUE(l.answer(s0, 0));
  l.request(0.1);
  EXPECT_FALSE(l.answer(s0, 0.1));  // late duplicate of step 0
  EXPECT_EQ(l.duplicates(), 1u);
  EXPECT_TRUE(l.pending());
}

TEST(Lockstep, GapsAndFutureAnswersAreErrors) {
  Follower f;
  EXPECT_THROW(f.on_request(3), ProtocolError);
  Leader l;
  l.request(0);
  EXPECT_THROW(l.answer(5, 0), ProtocolError);
  EXPECT_THROW(l.request(0), ProtocolError);  // step 0 still pending
}

TEST(Lockstep, SilentPeerTimesOutWithClearError) {
  Leader l({2.0, 0.5, 10.0});
  l.request(0);
  EXPECT_NO_THROW(l.check_timeout(9.0));   // first answer: the longer start-up limit
  EXPECT_THROW(l.check_timeout(10.5), ProtocolError);
  EXPECT_TRUE(l.answer(0, 10.4));
  l.request(11.0);
  EXPECT_NO_THROW(l.check_timeout(12.5));
  try {
    l.check_timeout(13.5);
    FAIL() << "no timeout";
  } catch (const ProtocolError& e) {
    EXPECT_NE(std::string(e.what()).find("step 1"), std::string::npos) << e.what();
  }
}

// Issue 22: on a busy machine one DEM step can take longer than timeout_s though the DEM is working. Heartbeats for
// the pending step (sent from inside the DEM's advance) restart the timeout: the limit is on the follower's silence.
TEST(Lockstep, HeartbeatsOfThePendingStepKeepASlowPeerAlive) {
  Leader l({2.0, 0.5, 10.0});
  l.request(0.0);
  EXPECT_TRUE(l.answer(0, 1.0));
  l.request(1.0);                             // step 1, limit 2 s
  for (double t = 2.5; t < 20.0; t += 1.5) {  // the DEM needs 19 s for it, beating every 1.5 s
    l.alive(1, t);
    EXPECT_NO_THROW(l.check_timeout(t + 1.9)) << t;
  }
  EXPECT_TRUE(l.answer(1, 20.0));
  l.request(20.0);
  l.alive(1, 20.5);  // a late heartbeat of step 1 says nothing about step 2
  l.alive(7, 20.5);  // nor one of a step never requested
  EXPECT_THROW(l.check_timeout(22.1), ProtocolError);
  l.alive(2, 21.0);
  l.alive(2, 21.5);
  EXPECT_NO_THROW(l.check_timeout(23.4));
  try {  // the heartbeats stop (the DEM stalls, or is stopped): a timeout 2 s after the last one, saying so
    l.check_timeout(23.6);
    FAIL() << "no timeout";
  } catch (const ProtocolError& e) {
    EXPECT_NE(std::string(e.what()).find("no answer from the DEM node for step 2"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("last heartbeat"), std::string::npos) << e.what();
  }
}

TEST(Lockstep, ResumedPairContinuesAtTheCheckpointStep) {
  Leader l({2.0, 0.5, 10.0});
  Follower f;
  l.resume_at(300);
  f.resume_at(300);
  auto s = l.request(0.0);
  EXPECT_EQ(s, 300u);
  EXPECT_NO_THROW(l.check_timeout(9.0));  // the peer loads its checkpoint: the first-answer limit
  EXPECT_EQ(f.on_request(299), Follower::Action::Resend);  // a stale request from before the stop
  EXPECT_EQ(f.on_request(s), Follower::Action::Advance);
  f.answered(s);
  EXPECT_TRUE(l.answer(s, 9.5));
  EXPECT_EQ(l.completed(), 301u);
  l.request(10.0);
  EXPECT_THROW(l.check_timeout(12.5), ProtocolError);  // then the running limit
  EXPECT_THROW(f.on_request(302), ProtocolError);      // a gap after a resume is still an error
  Leader late;
  late.request(0.0);
  EXPECT_THROW(late.resume_at(5), ProtocolError);  // only before the first request
  Follower g;
  EXPECT_THROW(g.resume_at(0), ProtocolError);
  // Only one node resumed: the error says so instead of waiting for a timeout or blaming a lost step.
  auto message = [](Follower& f, std::uint64_t step) {
    try {
      f.on_request(step);
    } catch (const ProtocolError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  Follower resumed;
  resumed.resume_at(300);
  EXPECT_NE(message(resumed, 0).find("~resume:=true to both nodes"), std::string::npos) << message(resumed, 0);
  Follower fresh;
  EXPECT_NE(message(fresh, 300).find("~resume:=true to both nodes"), std::string::npos) << message(fresh, 300);
}
