#pragma once
// The MBD-DEM lockstep protocol as a ROS-free state machine (Figure 13 of the paper).
// The mechanism (leader) publishes liner poses for coupling step k; the DEM (follower) advances over
// [t_k, t_k + dt] and answers with the time-averaged wrench for step k; the leader applies it over the
// same interval and only then moves on to k + 1. Either side may start first: the leader repeats an
// unanswered request every `resend_s`, and the follower answers a repeated request from its cache.
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>

namespace coupling {

class ProtocolError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct LeaderOptions {
  // no answer and no heartbeat (alive) for this long (wall time): the peer is gone. A follower that sends heartbeats
  // while it works may take longer than this for a step on a busy machine: the limit is on its silence.
  double timeout_s = 30.0;
  double resend_s = 0.5;     // repeat the pending request this often (peer may start late)
  double first_timeout_s = 120.0;  // longer wait for the very first answer (peer start-up, packing)
};

// Leader side (mbd_node). Wall time is passed in so that tests control it.
class Leader {
 public:
  explicit Leader(LeaderOptions o = {}) : o_(o) {}

  // Step k is being requested now; returns its counter.
  std::uint64_t request(double now_s);
  // An answer arrived. Returns true when it completes the pending step; stale duplicates (an old step
  // answered twice) return false and are counted; an answer from the future throws.
  bool answer(std::uint64_t step, double now_s);
  // The follower is working on `step` (a heartbeat it sends from inside its computation, so only while it makes
  // progress). For the pending step the timeout starts again from now; any other step (a late heartbeat of a step
  // answered already) changes nothing.
  void alive(std::uint64_t step, double now_s);
  // Whether the pending request should be sent again now.
  bool should_resend(double now_s);
  // Throws ProtocolError if the peer has been silent too long.
  void check_timeout(double now_s) const;
  // Resuming from a checkpoint taken before step `step`: the next request is `step`, and its answer gets the
  // first-answer timeout (the peer loads its own checkpoint first).
  void resume_at(std::uint64_t step);

  bool pending() const { return pending_.has_value(); }
  std::uint64_t completed() const { return completed_; }  // steps answered so far
  std::uint64_t duplicates() const { return duplicates_; }

 private:
  LeaderOptions o_;
  std::optional<std::uint64_t> pending_;
  std::uint64_t next_ = 0, completed_ = 0, duplicates_ = 0, start_ = 0;
  double sent_at_ = 0, last_send_ = 0, heard_at_ = 0;  // heard_at_: the last heartbeat for the pending step
};

// Follower side (dem_node).
class Follower {
 public:
  enum class Action { Advance, Resend, Ignore };
  // A request for `step` arrived: Advance (new step, the next expected one), Resend (the step just answered,
  // asked again), Ignore (older). A gap (a step skipped) throws: the two solvers would no longer agree.
  Action on_request(std::uint64_t step);
  void answered(std::uint64_t step);  // the reply for `step` was sent
  // Resuming from a checkpoint taken before step `step` (> 0): `step` is the next expected request.
  void resume_at(std::uint64_t step);
  std::optional<std::uint64_t> last_answered() const { return last_; }
  std::uint64_t advanced() const { return advanced_; }

 private:
  std::optional<std::uint64_t> last_, resumed_at_;
  std::uint64_t advanced_ = 0;
};

}  // namespace coupling
