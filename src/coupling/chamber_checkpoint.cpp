// ChamberDem checkpoints: the chamber's own bookkeeping around dem::World's state (core/binary_io.hpp).
#include <cmath>
#include <string>
#include <vector>

#include "coupling/chamber_dem.hpp"

namespace coupling {

namespace {

// What fixes the meaning of the saved state: the rocks (shapes, metaparticles, bonds), the liners, the
// screening and the crushing law. The amounts fed and the duration may change (a resumed run may be extended).
std::vector<double> fingerprint(const ChamberDem& d) {
  const auto& p = d.params();
  const auto& b = p.bpm.bond;
  std::vector<double> f{static_cast<double>(d.rock_shapes()), p.dt_s, p.feed.rock_size_m,
                        static_cast<double>(p.feed.seed), static_cast<double>(p.liner_sectors), p.discharge_below_m,
                        p.bookkeeping_s, static_cast<double>(p.rings), static_cast<double>(p.sectors),
                        b.kn, b.kt, b.sigma_c, b.tau_c, b.disk_radius, b.reference_radius, b.damping,
                        p.crushing.enabled ? 1.0 : 0.0, p.crushing.tensile_strength, p.crushing.progeny_exponent,
                        p.crushing.batch_s, p.crushing.fragments ? 1.0 : 0.0, p.crushing.min_fragment_m,
                        p.crushing.fragment_growth_s, p.crushing.stress_criterion ? 1.0 : 0.0};
  // Only with the size effect on, so that checkpoints written before it existed still load.
  if (p.crushing.size_exponent != 0) f.insert(f.end(), {p.crushing.size_exponent, p.crushing.reference_size});
  if (p.feed.rock_density > 0) f.push_back(p.feed.rock_density);  // likewise
  if (p.fines_flow) {  // the flow model that carries the fines: its cells, sieves and material
    const auto& q = p.fines;
    const std::vector<double> rock = chamber::material_fingerprint(q.material);
    const std::vector<double> laws = chamber::law_fingerprint(q.material);
    f.insert(f.end(), {-1.0, static_cast<double>(q.bands), static_cast<double>(q.sectors),
                       q.compaction_memory ? 1.0 : 0.0});
    f.insert(f.end(), rock.begin(), rock.end());
    f.insert(f.end(), laws.begin(), laws.end());
    f.push_back(static_cast<double>(q.sieves_m.size()));
    f.insert(f.end(), q.sieves_m.begin(), q.sieves_m.end());
  }
  for (const auto* v : {&p.sieves_m, &p.chamber.mantle.z, &p.chamber.mantle.r, &p.chamber.concave.z,
                        &p.chamber.concave.r}) {
    f.push_back(static_cast<double>(v->size()));
    f.insert(f.end(), v->begin(), v->end());
  }
  for (int s = 0; s < d.rock_shapes(); ++s) f.push_back(static_cast<double>(d.rock_particles(s)));
  for (int s = 0; s < d.rock_shapes(); ++s) f.push_back(d.rock_mass_kg(s));
  return f;
}

}  // namespace

void ChamberDem::put_growing(core::BinaryWriter& w) const {
  std::vector<uint64_t> id;
  std::vector<double> rr;
  for (const auto& g : growing_) id.push_back(g.id), rr.push_back(g.r_end), rr.push_back(g.rate);
  w.put_vec(id);
  w.put_vec(rr);
}

void ChamberDem::get_growing(core::BinaryReader& r) {
  std::vector<uint64_t> id;
  std::vector<double> rr;
  r.get_vec(id);
  r.get_vec(rr);
  if (rr.size() != 2 * id.size()) r.fail("growing fragments are corrupt");
  growing_.clear();
  for (std::size_t k = 0; k < id.size(); ++k) growing_.push_back({id[k], rr[2 * k], rr[2 * k + 1]});
}

void ChamberDem::save_state(core::BinaryWriter& w) {
  if (!decomposed_) {
    write_state(w);
    return;
  }
  edit_whole([&] { write_state(w); });  // the whole charge, on the root; the run continues cut anew from it
}

void ChamberDem::write_state(core::BinaryWriter& w) {
  w.tag("CHMB");
  w.put_vec(fingerprint(*this));
  w.put<char>(prefilled_);
  for (double v : {prefilled_kg_, deepest_liner_overlap_, next_bookkeeping_, feed_credit_kg_, fed_kg_, discharged_kg_,
                   lost_kg_, force_window_s_, force_avg_.window()})
    w.put(v);
  w.put<int64_t>(fragments_out_);
  w.put<int64_t>(broken_total_);
  w.put(crushed_kg_);
  w.put<int64_t>(crushed_count_);
  w.put<int64_t>(fragmented_count_);
  w.put_vec(screened_kg_);
  put_growing(w);
  std::vector<double> log;
  for (const auto& [t, m] : discharge_log_) log.push_back(t), log.push_back(m);
  w.put_vec(log);
  w.put_vec(breaks_);
  w.put_vec(tracked_ids_);
  std::vector<uint64_t> track_id;
  std::vector<double> track_tx;
  for (const auto& p : tracks_) {
    track_id.push_back(p.id);
    track_tx.insert(track_tx.end(), {p.t, p.x.x(), p.x.y(), p.x.z()});
  }
  w.put_vec(track_id);
  w.put_vec(track_tx);
  w.put_vec(force_avg_.sums());
  for (int k = 0; k < 3; ++k) w.put(concave_origin_[k]);
  w.put_string(rng_.state());
  if (fines_) fines_->save_state(w);
  world_->save_state(w);
  w.tag("CEND");
}

void ChamberDem::load_state(core::BinaryReader& r) {
  focus(*whole_);  // decomposed: the whole charge is read, then cut anew
  r.expect("CHMB");
  std::vector<double> f;
  r.get_vec(f, 1000);
  if (f != fingerprint(*this))
    r.fail("written for another feed or chamber (rocks, bonds, liners, sieves, crushing, fines' flow model or time step "
           "differ from this configuration; only the amounts fed and the duration may change)");
  prefilled_ = r.get<char>() != 0;
  for (double* v : {&prefilled_kg_, &deepest_liner_overlap_, &next_bookkeeping_, &feed_credit_kg_, &fed_kg_,
                    &discharged_kg_, &lost_kg_, &force_window_s_})
    r.get(*v);
  const double map_window = r.get<double>();
  fragments_out_ = r.get<int64_t>();
  broken_total_ = r.get<int64_t>();
  r.get(crushed_kg_);
  crushed_count_ = r.get<int64_t>();
  fragmented_count_ = r.get<int64_t>();
  r.get_vec(screened_kg_);
  if (screened_kg_.size() != p_.sieves_m.size() + 1) r.fail("sieve classes differ from this configuration");
  get_growing(r);
  std::vector<double> log;
  r.get_vec(log);
  if (log.size() % 2) r.fail("discharge log is corrupt");
  discharge_log_.clear();
  for (std::size_t k = 0; k < log.size(); k += 2) discharge_log_.emplace_back(log[k], log[k + 1]);
  r.get_vec(breaks_);
  r.get_vec(tracked_ids_);
  std::vector<uint64_t> track_id;
  std::vector<double> track_tx;
  r.get_vec(track_id);
  r.get_vec(track_tx);
  if (track_tx.size() != 4 * track_id.size()) r.fail("trajectories are corrupt");
  tracks_.clear();
  for (std::size_t k = 0; k < track_id.size(); ++k)
    tracks_.push_back({track_id[k], track_tx[4 * k], {track_tx[4 * k + 1], track_tx[4 * k + 2], track_tx[4 * k + 3]}});
  std::vector<double> sums;
  r.get_vec(sums);
  if (sums.size() != static_cast<std::size_t>(p_.rings * p_.sectors)) r.fail("force-map regions differ");
  force_avg_.restore(std::move(sums), map_window);
  for (int k = 0; k < 3; ++k) r.get(concave_origin_[k]);
  if (!rng_.set_state(r.get_string())) r.fail("random generator state is corrupt");
  if (fines_) fines_->load_state(r);
  world_->load_state(r);
  r.expect("CEND");
  if (make_engine_) start_engine();
}

}  // namespace coupling
