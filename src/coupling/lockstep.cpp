#include "coupling/lockstep.hpp"

namespace coupling {

std::uint64_t Leader::request(double now_s) {
  if (pending_) throw ProtocolError("coupling: step " + std::to_string(*pending_) + " is still unanswered");
  pending_ = next_++;
  sent_at_ = last_send_ = heard_at_ = now_s;
  return *pending_;
}

void Leader::alive(std::uint64_t step, double now_s) {
  if (pending_ && step == *pending_ && now_s > heard_at_) heard_at_ = now_s;
}

bool Leader::answer(std::uint64_t step, double now_s) {
  if (pending_ && step == *pending_) {
    pending_.reset();
    ++completed_;
    return true;
  }
  if (step < next_) {  // an old step answered again (the follower answered a resend)
    ++duplicates_;
    return false;
  }
  throw ProtocolError("coupling: answer for step " + std::to_string(step) + " but only " +
                      std::to_string(next_) + " steps were requested");
}

bool Leader::should_resend(double now_s) {
  if (!pending_ || now_s - last_send_ < o_.resend_s) return false;
  last_send_ = now_s;
  return true;
}

void Leader::check_timeout(double now_s) const {
  if (!pending_) return;
  double limit = completed_ == start_ ? o_.first_timeout_s : o_.timeout_s;
  if (now_s - heard_at_ > limit) {
    const bool beat = heard_at_ > sent_at_;
    throw ProtocolError("coupling: no answer from the DEM node for step " + std::to_string(*pending_) + " within " +
                        std::to_string(limit) + " s" +
                        (beat ? " of its last heartbeat (it stopped making progress)" : " (and no heartbeat)") +
                        "; is dem_node running on the same master?");
  }
}

Follower::Action Follower::on_request(std::uint64_t step) {
  std::uint64_t expected = last_ ? *last_ + 1 : 0;
  if (step == expected) {
    ++advanced_;
    return Action::Advance;
  }
  if (last_ && step == *last_) return Action::Resend;
  if (resumed_at_ && step + 1 < *resumed_at_)
    throw ProtocolError("coupling: request for step " + std::to_string(step) + ", but this node resumed from the "
                        "checkpoint at step " + std::to_string(*resumed_at_) +
                        ": give ~resume:=true to both nodes, or to neither");
  if (last_ && step < *last_) return Action::Ignore;
  if (expected == 0 && step > 0)
    throw ProtocolError("coupling: request for step " + std::to_string(step) + " before any step 0: the leader "
                        "resumed from a checkpoint; give ~resume:=true to both nodes, or to neither");
  throw ProtocolError("coupling: request for step " + std::to_string(step) + " but step " +
                      std::to_string(expected) + " was expected (a step was lost; restart both nodes)");
}

void Leader::resume_at(std::uint64_t step) {
  if (pending_ || next_ != 0) throw ProtocolError("coupling: resume_at must come before the first request");
  next_ = completed_ = start_ = step;
}

void Follower::answered(std::uint64_t step) { last_ = step; }

void Follower::resume_at(std::uint64_t step) {
  if (step == 0) throw ProtocolError("coupling: a checkpoint is taken after step 0, not before it");
  if (last_) throw ProtocolError("coupling: resume_at must come before the first request");
  last_ = step - 1;
  advanced_ = step;
  resumed_at_ = step;
}

}  // namespace coupling
