// Full diagnosis of plant-style exports made from the mechanism itself (issue 24, plant inputs): the
// model's own output written as a DAQ export (semicolon, decimal comma, mm / kW / rpm or accelerations,
// speed logged at its set point, values rounded to a logger resolution, NaN rows, a gap, another sample
// rate) and read back through the column map. Nothing concealed must give `none`; an acceleration-only
// export with a concealed effect must name it.
#include <gtest/gtest.h>

#include <random>

#include "analysis/diagnosis.hpp"
#include "analysis/mbd_model.hpp"
#include "analysis/plant_export.hpp"
#include "analysis/sensor_model.hpp"
#include "core/config.hpp"
#include "core/units.hpp"
#include "mbd/simulate.hpp"

using namespace analysis;

namespace {

mbd::MechanismParams base_params() {
  auto root = core::ConfigNode::load_file(std::string(CRUSHER_SOURCE_DIR) + "/launch_free_configs/gyp1200_400rpm_bed.yaml");
  return mbd::load_mechanism_params(root.child("mbd"));
}

struct PlantCase {
  double rpm;
  std::string effect = "none";
  double value = 0;
  double noise_rel = 0.003;
  double sample_hz = 1000;
  double seconds = 2.5;
  double time_offset_s = 0.02, gain = 1.0;
  std::uint64_t seed = 1;
  int missing_rows = 0;
  double gap_t0 = -1, gap_s = 0;     // seconds left out, from the start
  bool speed_setpoint = true;        // speed logged constant at the set point
  double az_bias = 0;                // added to az (gravity on a vertical accelerometer)
  std::array<double, 3> zero_offset_mm{};  // a displacement sensor not zeroed at the machine's rest
  bool zero_unknown = false;         // read back with --zero-unknown x,y,z
};

// The export as the plant's logger writes it (format.resolution rounds), read back as the user would:
// with `read` (the resolution stated or left to the data).
Recording plant_recording(const mbd::MechanismParams& base, const PlantCase& c, const PlantFormat& written,
                          const PlantFormat& read, const std::string& name) {
  mbd::SimOptions so;
  so.duration_s = c.seconds;
  so.settle_s = MbdModelOptions().settle_s;
  so.sample_hz = c.sample_hz;
  const auto p = with_effect(at_speed(base, c.rpm * core::units::rpm), c.effect, c.value);
  Recording model = from_fields(mbd::simulate(p, so), "");
  if (written.columns.count(kAx)) model = with_acceleration(model);
  SensorErrors e;
  e.noise_rel = c.noise_rel;
  e.time_offset_s = c.time_offset_s;
  e.gain = c.gain;
  e.seed = c.seed;
  for (int i = 0; i < 3; ++i) e.zero_offset_m[i] = c.zero_offset_mm[i] * 1e-3;
  Recording rec = apply_sensor_errors(model, e);
  if (c.speed_setpoint) rec.speed_rad_s.assign(rec.size(), c.rpm * core::units::rpm);
  for (double& a : rec.az_m_s2) a += c.az_bias;
  if (c.gap_t0 >= 0) {
    const double t0 = rec.t_s.front();
    Recording a = rec.slice(t0, t0 + c.gap_t0), b = rec.slice(t0 + c.gap_t0 + c.gap_s, rec.t_s.back() + 1);
    for (std::size_t i = 0; i < b.size(); ++i) {
      a.t_s.push_back(b.t_s[i]);
      for (int ch = 0; ch < kNumChannels; ++ch)
        if (b.has(ch)) a.channel(ch).push_back(b.channel(ch)[i]);
    }
    rec = a;
  }
  std::vector<std::size_t> missing;
  std::mt19937_64 rng(c.seed + 3);
  for (int i = 0; i < c.missing_rows; ++i) missing.push_back(rng() % rec.size());
  const std::string path = ::testing::TempDir() + name;
  write_plant_export(rec, path, written, missing);
  Recording back = read_plant_export(path, read);
  back.source = name;
  if (c.zero_unknown) back.zero_unknown = parse_zero_unknown("x,y,z");
  return back;
}

PlantFormat format(const std::string& columns, const std::string& resolution) {
  PlantFormat f;
  f.columns = parse_column_map(columns);
  f.delimiter = ';';
  f.decimal = ',';
  parse_resolutions(resolution, f);
  return f;
}
PlantFormat without_resolution(PlantFormat f) {
  f.resolution = {};
  return f;
}

std::string notes(const DiagnosisResult& r) {
  std::string s;
  for (const auto& d : r.train)
    for (const auto& n : d.rec.notes) s += n + "\n";
  return s;
}

}  // namespace

// Two speeds, displacement in mm, power in kW, speed logged at its set point in rpm, rounded to the
// logger's steps (not told: estimated from the data), NaN rows and a gap, 500 and 150 Hz.
TEST(DiagPlant, ExportOfTheModelItselfGivesNone) {
  const auto base = base_params();
  const PlantFormat f = format("t=time[ms],x=disp_x[mm],y=disp_y[mm],z=disp_z[mm],power=P[kW],speed=n[rpm]",
                               "x=0.01,y=0.01,z=0.01,power=0.1,speed=1");
  PlantCase a{400};
  a.sample_hz = 500;
  a.missing_rows = 7;
  a.gap_t0 = 1.1;
  a.gap_s = 0.23;
  a.seed = 31;
  PlantCase b{600};
  b.sample_hz = 150;  // 15 samples per drive period: orders up to 7 are fitted
  b.noise_rel = 0.002;
  b.missing_rows = 3;
  b.time_offset_s = 0.007;
  b.seed = 32;
  std::vector<Recording> recs = {plant_recording(base, a, f, without_resolution(f), "plant400.csv"),
                                 plant_recording(base, b, f, without_resolution(f), "plant600.csv")};
  DiagnosisResult r = diagnose(recs, make_mbd_model(base), mbd_candidates());
  EXPECT_EQ(r.effect, "none") << r.reason << "\n" << notes(r) << diagnosis_markdown(r);
  EXPECT_FALSE(r.residual_significant);
  // The set point is taken as such, the resolution found in the data, the skipped rows and gap reported.
  EXPECT_FALSE(r.train[0].use[kSpeed].compared);
  EXPECT_EQ(r.train[0].use[kSpeed].why_not, "set point");
  EXPECT_NEAR(r.train[0].setpoint, 400 * core::units::rpm, 1e-9);
  EXPECT_NEAR(r.heldout[0].setpoint, 600 * core::units::rpm, 1e-9);
  EXPECT_NEAR(r.train[0].use[kX].resolution, 1e-5, 1e-11);
  EXPECT_NEAR(r.train[0].use[kPower].resolution, 100, 1e-6);
  EXPECT_EQ(r.heldout[0].H[kX].orders(), 7);
  const std::string n = notes(r);
  EXPECT_NE(n.find("row(s) with a missing value skipped"), std::string::npos) << n;
  EXPECT_NE(n.find("gap(s) longer than 1.5 steps"), std::string::npos) << n;
  EXPECT_NE(n.find("the largest 0.23"), std::string::npos) << n;  // the 0.23 s cut (plus one step)
  const std::string json = diagnosis_json(r);
  EXPECT_NE(json.find("\"speed_rad_s\": {\"use\": \"set point\""), std::string::npos);
  EXPECT_NE(diagnosis_markdown(r).find("speed_rad_s = 41.88790"), std::string::npos);
}

// One speed between the two, the logger's resolution stated, the speed measured but varying only by its
// resolution (0.5 rpm), a coarser power step, another sample rate and noise level.
TEST(DiagPlant, ExportWithStatedResolutionAndFlickeringSpeedGivesNone) {
  const auto base = base_params();
  const PlantFormat f = format("t=t[s],x=sx[mm],y=sy[mm],power=Pm[W],speed=f[Hz]",
                               "x=0.02mm,y=0.02mm,power=500W,speed=0.5rpm");
  PlantCase c{470};
  c.sample_hz = 400;
  c.seconds = 4.0;
  c.noise_rel = 0.006;
  c.speed_setpoint = false;
  c.missing_rows = 12;
  c.time_offset_s = 0.051;
  c.gain = 1.03;
  c.seed = 77;
  std::vector<Recording> recs = {plant_recording(base, c, f, f, "plant470.txt")};
  EXPECT_FALSE(recs[0].has(kZ));
  DiagnosisResult r = diagnose(recs, make_mbd_model(base), mbd_candidates());
  EXPECT_EQ(r.effect, "none") << r.reason << "\n" << notes(r) << diagnosis_markdown(r);
  EXPECT_FALSE(r.train[0].use[kSpeed].compared);
  EXPECT_FALSE(r.train[0].use[kZ].compared);
  EXPECT_FALSE(r.train[0].use[kX].resolution_estimated);
  EXPECT_NEAR(r.train[0].use[kPower].resolution, 500, 1e-9);
  EXPECT_NEAR(r.before_train[0].alignment.gain, 1.03, 0.01);
}

// Accelerometers instead of displacement sensors (m/s^2 and g, gravity on the vertical one), a concealed
// effect: it is named and fitted as from displacement (test_diag_mbd: joint_friction within 15 %).
TEST(DiagPlant, AccelerationOnlyExportNamesConcealedFriction) {
  const auto base = base_params();
  const PlantFormat f = format("t=time[s],ax=acc_x[m/s^2],ay=acc_y[m/s^2],az=acc_z[g],power=P[kW],speed=n[rpm]",
                               "ax=0.01,ay=0.01,az=0.001,power=0.1");
  std::vector<Recording> recs;
  int i = 0;
  for (double rpm : {400.0, 600.0}) {
    PlantCase c{rpm, "joint_friction", 450.0};
    c.noise_rel = 0.004;
    c.sample_hz = rpm == 400 ? 1000 : 750;
    c.gain = 0.98;
    c.time_offset_s = 0.024 + 0.01 * i;
    c.missing_rows = 4;
    c.seed = 50 + i++;
    c.az_bias = 9.80665;  // the vertical accelerometer feels gravity
    recs.push_back(plant_recording(base, c, f, without_resolution(f), "acc" + std::to_string(int(rpm)) + ".csv"));
  }
  EXPECT_FALSE(recs[0].has(kX));
  DiagnosisResult r = diagnose(recs, make_mbd_model(base), mbd_candidates());
  ASSERT_EQ(r.effect, "joint_friction") << r.reason << "\n" << diagnosis_markdown(r);
  const auto& fit = r.candidates[r.chosen];
  EXPECT_NEAR(fit.value, 450.0, 0.15 * 450.0);
  EXPECT_LT(fit.sigma, 0.15 * 450.0);
  // The structured (harmonic) residual is gone on the held-out speed. (The overall NRMSE is not the measure
  // here: the model's acceleration has broadband content above order 12 that sets its noise floor.)
  EXPECT_GT(fit.explained_heldout, 0.9);
  EXPECT_FALSE(residual_significant(r.after_heldout[0].ch[kAx]));
  EXPECT_NEAR(r.after_train[0].alignment.gain, 0.98, 0.01);
  EXPECT_TRUE(r.train[0].use[kAz].compared);
}

// The same accelerometers on the model itself, one speed (split in time): nothing to name. (Taking the
// model's acceleration as -(k w)^2 times its displacement harmonics amplified the leak of the model's slow
// drift into orders 7-12 and gave `unexplained: az_m_s2 order 7-12` here.)
TEST(DiagPlant, AccelerationOnlyExportOfTheModelGivesNone) {
  const auto base = base_params();
  const PlantFormat f = format("t=t[ms],ax=ax[mm/s^2],ay=ay[mm/s^2],az=az[m/s^2],power=P[kW],speed=n[rpm]",
                               "ax=5,ay=5,az=0.005,power=0.2");
  PlantCase c{400};
  c.noise_rel = 0.002;
  c.seconds = 3.5;
  c.time_offset_s = 0.061;
  c.missing_rows = 6;
  c.az_bias = 9.80665;
  c.seed = 64;
  std::vector<Recording> recs = {plant_recording(base, c, f, without_resolution(f), "acc_none.csv")};
  DiagnosisResult r = diagnose(recs, make_mbd_model(base), mbd_candidates());
  EXPECT_EQ(r.effect, "none") << r.reason << "\n" << diagnosis_markdown(r);
}

// Displacement sensors not zeroed at the machine's rest (offsets of 1.3, -0.8 and 2.1 mm, of the order of the
// motion's amplitude): read with --zero-unknown x,y,z their means are not compared and the model itself gives none;
// compared, the offsets alone are a significant mismatch (what the tool would otherwise have to explain).
TEST(DiagPlant, DisplacementSensorsOfUnknownZeroGiveNone) {
  const auto base = base_params();
  const PlantFormat f = format("t=time[s],x=dx[mm],y=dy[mm],z=dz[mm],power=P[kW],speed=n[rpm]", "");
  std::vector<Recording> recs, compared;
  for (double rpm : {400.0, 600.0}) {
    PlantCase c{rpm};
    c.zero_offset_mm = {1.3, -0.8, 2.1};
    c.seed = rpm == 400 ? 41 : 42;
    c.time_offset_s = rpm == 400 ? 0.013 : 0.004;
    c.zero_unknown = true;
    recs.push_back(plant_recording(base, c, f, f, "zero" + std::to_string(int(rpm)) + ".csv"));
    c.zero_unknown = false;
    compared.push_back(plant_recording(base, c, f, f, "zero_compared" + std::to_string(int(rpm)) + ".csv"));
  }
  DiagnosisResult r = diagnose(recs, make_mbd_model(base), mbd_candidates());
  EXPECT_EQ(r.effect, "none") << r.reason << "\n" << diagnosis_markdown(r);
  EXPECT_FALSE(r.residual_significant);
  EXPECT_FALSE(r.train[0].use[kX].mean_compared);
  EXPECT_TRUE(r.train[0].use[kPower].mean_compared);
  EXPECT_NE(diagnosis_json(r).find("not compared (sensor zero unknown)"), std::string::npos);
  const DiagnosisResult c = diagnose(compared, make_mbd_model(base), mbd_candidates());
  EXPECT_TRUE(c.effect != "none" || c.residual_significant) << c.reason;
}

TEST(DiagPlant, ZeroUnknownTakesDisplacementChannelsOnly) {
  const auto z = parse_zero_unknown("x,z");
  EXPECT_TRUE(z[kX] && z[kZ] && !z[kY] && !z[kPower]);
  try {
    parse_zero_unknown("x,power");
    FAIL() << "expected a throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'power'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("accepted: x, y, z"), std::string::npos) << e.what();
  }
}
