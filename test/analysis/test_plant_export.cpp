// Plant exports (column map with units, delimiter, decimal comma, missing rows, gaps, logger resolution)
// and the noise floor's quantisation and set-point channels (issue 24, plant inputs).
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <sstream>
#include <fstream>
#include <random>

#include "analysis/comparison.hpp"
#include "analysis/plant_export.hpp"
#include "analysis/quantisation.hpp"
#include "analysis/sensor_model.hpp"
#include "diag_synthetic_model.hpp"

using namespace analysis;

namespace {

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "no error";
}

PlantFormat daq_format() {
  PlantFormat f;
  f.columns = parse_column_map("t=time[s],x=disp_x[mm],y=disp_y[mm],z=disp_z[mm],power=P[kW],speed=n[rpm]");
  f.delimiter = ';';
  f.decimal = ',';
  return f;
}

// A small DAQ-style file: extra columns, decimal commas, mm, kW, rpm.
std::string daq_text(int rows, double dt = 2e-3) {
  std::string s = "time[s];status;disp_x[mm];disp_y[mm];disp_z[mm];P[kW];n[rpm];temp[C]\n";
  for (int i = 0; i < rows; ++i) {
    char line[256];
    const double t = i * dt, w = 41.9;
    std::snprintf(line, sizeof line, "%.4f;ok;%.3f;%.3f;%.3f;%.1f;%.1f;21,5\n", t, 5 * std::cos(w * t),
                  5 * std::sin(w * t), 0.5 * std::cos(2 * w * t), 76 + 3 * std::cos(2 * w * t), 400.0);
    std::string l(line);
    for (char& c : l) if (c == '.') c = ',';
    s += l;
  }
  return s;
}

}  // namespace

TEST(PlantExport, ReadsDaqExportInSiUnits) {
  Recording r = parse_plant_export(daq_text(200), "daq.csv", daq_format());
  ASSERT_EQ(r.size(), 200u);
  EXPECT_NEAR(r.x_m[0], 5e-3, 1e-9);       // 5,000 mm
  EXPECT_NEAR(r.power_W[0], 79e3, 1e-6);   // 79,0 kW
  EXPECT_NEAR(r.speed_rad_s[5], 400 * 2 * M_PI / 60, 1e-12);
  EXPECT_NEAR(r.t_s[3], 6e-3, 1e-12);
  EXPECT_FALSE(r.has(kAx));                // not mapped: not recorded
  // Time in ms and acceleration in g: unit factors.
  PlantFormat f;
  f.columns = parse_column_map("t=ms[ms],ax=a[g],speed=f[Hz]");
  std::string text = "ms,a,f\n";
  for (int i = 0; i < 60; ++i) text += std::to_string(i) + ",0.5,6\n";
  Recording a = parse_plant_export(text, "acc.csv", f);
  EXPECT_NEAR(a.t_s[10], 0.010, 1e-12);
  EXPECT_NEAR(a.ax_m_s2[0], 0.5 * 9.80665, 1e-12);
  EXPECT_NEAR(a.speed_rad_s[0], 6 * 2 * M_PI, 1e-12);
  EXPECT_FALSE(a.has(kX));
  // A spreadsheet's byte-order mark and quoted cells holding the delimiter.
  f.columns = parse_column_map("t=time[s],x=x[mm],speed=n[rpm]");
  f.decimal = ',';
  f.delimiter = ';';
  text = "\xEF\xBB\xBF\"time\";\"x\";\"n\"\n";
  for (int i = 0; i < 60; ++i) text += "\"" + std::to_string(i) + ",5\";\"1,25\";\"400\"\n";
  Recording q = parse_plant_export(text, "bom.csv", f);
  EXPECT_NEAR(q.t_s[2], 2.5, 1e-12);
  EXPECT_NEAR(q.x_m[0], 1.25e-3, 1e-15);
}

TEST(PlantExport, SkipsAndReportsMissingRowsAndGaps) {
  std::string text = daq_text(300);
  // A unit row after the header, NaN and empty cells, and 40 rows cut out (a gap of 80 ms).
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  lines.insert(lines.begin() + 1, "s;-;mm;mm;mm;kW;1/min;C");
  lines[11] = "0,0200;ok;NaN;1,0;1,0;70,0;400,0;21,5";  // line 12 of the file
  lines[50] = "0,0980;ok;1,0;;1,0;70,0;400,0;21,5";     // line 51
  lines.erase(lines.begin() + 100, lines.begin() + 140);
  std::string t2;
  for (const auto& l : lines) t2 += l + "\n";
  Recording r = parse_plant_export(t2, "daq.csv", daq_format());
  EXPECT_EQ(r.size(), 300u - 2 - 40);
  std::string notes;
  for (const auto& n : r.notes) notes += n + "\n";
  EXPECT_NE(notes.find("unit row at line 2 skipped"), std::string::npos) << notes;
  EXPECT_NE(notes.find("2 row(s) with a missing value skipped, first at line 12"), std::string::npos) << notes;
  EXPECT_NE(notes.find("3 gap(s)"), std::string::npos) << notes;  // the cut and the two skipped rows
  EXPECT_NE(notes.find("the largest 0.082 s after t = 0.194 s"), std::string::npos) << notes;
}

TEST(PlantExport, BadFilesNameTheRowOrColumn) {
  const PlantFormat f = daq_format();
  std::string m = error_of([&] { parse_plant_export(daq_text(100), "a.csv", [&] {
    PlantFormat g = f;
    g.delimiter = ',';
    g.decimal = '.';
    return g;
  }()); });
  // Wrong delimiter: the map's column is not in the header, which looks ';'-separated.
  EXPECT_NE(m.find("a.csv:1: column 'time' (t) is not in the header"), std::string::npos) << m;
  EXPECT_NE(m.find("--delimiter ';'"), std::string::npos) << m;
  // Decimal point expected, decimal comma found: row and column named, the flag suggested.
  m = error_of([&] { PlantFormat g = f; g.decimal = '.'; parse_plant_export(daq_text(100), "b.csv", g); });
  EXPECT_NE(m.find("b.csv:2: column 'time'"), std::string::npos) << m;
  EXPECT_NE(m.find("--decimal ,"), std::string::npos) << m;
  // Same character for both.
  m = error_of([&] { PlantFormat g = f; g.delimiter = ','; parse_plant_export(daq_text(100), "c.csv", g); });
  EXPECT_NE(m.find("delimiter and decimal separator are both ','"), std::string::npos) << m;
  // A mapped column missing from the header.
  m = error_of([&] {
    PlantFormat g = f;
    g.columns = parse_column_map("t=time[s],x=disp_x[mm],power=Pel[kW],speed=n[rpm]");
    parse_plant_export(daq_text(100), "d.csv", g);
  });
  EXPECT_NE(m.find("column 'Pel' (power) is not in the header"), std::string::npos) << m;
  // Time not increasing.
  std::string t = daq_text(100);
  t += "0,0100;ok;1,0;1,0;1,0;70,0;400,0;21,5\n";
  m = error_of([&] { parse_plant_export(t, "e.csv", f); });
  EXPECT_NE(m.find("e.csv:102: column 'time': time 0.01 s does not increase"), std::string::npos) << m;
  // Text in a value.
  t = daq_text(100) + "0,5;ok;1,0;abc;1,0;70,0;400,0;21,5\n";
  m = error_of([&] { parse_plant_export(t, "f.csv", f); });
  EXPECT_NE(m.find("f.csv:102: column 'disp_y': 'abc' is not a number"), std::string::npos) << m;
  // Too few rows; too many missing.
  m = error_of([&] { parse_plant_export(daq_text(20), "g.csv", f); });
  EXPECT_NE(m.find("only 20 usable data rows"), std::string::npos) << m;
  t = daq_text(60);
  for (int i = 0; i < 70; ++i) t += std::to_string(1 + i) + ";ok;nan;1;1;70;400;21\n";
  m = error_of([&] { parse_plant_export(t, "h.csv", f); });
  EXPECT_NE(m.find("70 of 130 rows lack a mapped value (first at line 62)"), std::string::npos) << m;
  // A stopped drive.
  t = daq_text(60) + "1,0;ok;1,0;1,0;1,0;70,0;0,0;21,5\n";
  m = error_of([&] { parse_plant_export(t, "i.csv", f); });
  EXPECT_NE(m.find("i.csv:62: column 'n': speed must be positive"), std::string::npos) << m;
  // No speed and no set point.
  m = error_of([&] {
    PlantFormat g = f;
    g.columns = parse_column_map("t=time[s],x=disp_x[mm]");
    parse_plant_export(daq_text(100), "j.csv", g);
  });
  EXPECT_NE(m.find("no speed column"), std::string::npos) << m;
  EXPECT_NE(m.find("--setpoint-rpm"), std::string::npos) << m;
}

TEST(PlantExport, ColumnMapAndResolutionSyntax) {
  std::string m = error_of([] { parse_column_map("t=time[s],x=disp_x[inch]"); });
  EXPECT_NE(m.find("unit 'inch' for x (displacement) is not known; accepted: m, mm, um"), std::string::npos) << m;
  m = error_of([] { parse_column_map("t=time[s],x=disp_x"); });
  EXPECT_NE(m.find("'x=disp_x': the column's unit is missing"), std::string::npos) << m;
  m = error_of([] { parse_column_map("t=time[s],w=disp_x[mm]"); });
  EXPECT_NE(m.find("unknown key 'w'"), std::string::npos) << m;
  m = error_of([] { parse_column_map("t=time[s],power=P[kW],speed=n[rpm]"); });
  EXPECT_NE(m.find("no test-point channel"), std::string::npos) << m;
  m = error_of([] { parse_column_map("x=disp_x[mm]"); });
  EXPECT_NE(m.find("no time column"), std::string::npos) << m;
  m = error_of([] { parse_column_map("t=time[s],x=a[mm],y=a[mm]"); });
  EXPECT_NE(m.find("column 'a' is mapped to both x and y"), std::string::npos) << m;
  m = error_of([] { parse_column_map("t=time[s],speed=n[rpm],ax=acc[m/s]"); });
  EXPECT_NE(m.find("accepted: m/s^2, m/s2, mm/s^2, mm/s2, g"), std::string::npos) << m;
  // Header names that carry their unit, and units in brackets with spaces.
  auto cols = parse_column_map("t=Zeit[s], x=Weg X[mm], speed=Drehzahl[U/min]");
  EXPECT_EQ(cols.at(kX).column, "Weg X");
  EXPECT_NEAR(cols.at(kSpeed).to_si, 2 * M_PI / 60, 1e-15);
  PlantFormat f;
  f.columns = cols;
  std::string text = "Zeit [s];Weg X [mm];Drehzahl [U/min]\n";
  for (int i = 0; i < 60; ++i) text += std::to_string(i) + ";1;400\n";
  f.delimiter = ';';
  EXPECT_NEAR(parse_plant_export(text, "k.csv", f).x_m[0], 1e-3, 1e-15);
  // Resolution: in the column's unit when none is given, or in its own.
  parse_resolutions("x=0.01,speed=1rpm,power=0.1kW", f);
  EXPECT_NEAR(f.resolution[kX], 1e-5, 1e-18);
  EXPECT_NEAR(f.resolution[kSpeed], 2 * M_PI / 60, 1e-15);
  EXPECT_NEAR(f.resolution[kPower], 100, 1e-12);
  m = error_of([&] { parse_resolutions("x=0", f); });
  EXPECT_NE(m.find("positive number"), std::string::npos) << m;
  m = error_of([&] { parse_resolutions("power=0.1kWh", f); });
  EXPECT_NE(m.find("unit 'kWh' for power"), std::string::npos) << m;
}

TEST(PlantExport, WriteReadRoundTripRoundsToResolution) {
  Recording r = diagtest::synthetic_run("none", 0, 45.0, 0.5);
  r = with_acceleration(r);
  PlantFormat f;
  f.columns = parse_column_map("t=t[ms],x=x[mm],y=y[um],az=a[g],power=p[kW],speed=n[rpm]");
  f.delimiter = '\t';
  f.decimal = ',';
  parse_resolutions("x=0.01,power=0.1,az=0.001", f);
  const std::string path = ::testing::TempDir() + "plant_roundtrip.txt";
  write_plant_export(r, path, f, {3, 17});
  Recording b = read_plant_export(path, f);
  ASSERT_EQ(b.size(), r.size() - 2);
  EXPECT_FALSE(b.has(kZ));
  for (std::size_t i : {0u, 10u, 200u}) {
    const std::size_t j = i < 3 ? i : (i < 15 ? i + 1 : i + 2);  // rows 3 and 17 were written as NaN
    EXPECT_NEAR(b.t_s[i], r.t_s[j], 1e-12);
    EXPECT_NEAR(b.x_m[i], r.x_m[j], 0.5e-5 + 1e-12);
    EXPECT_NEAR(b.y_m[i], r.y_m[j], 1e-12);
    EXPECT_NEAR(b.az_m_s2[i], r.az_m_s2[j], 0.5e-3 * 9.80665 + 1e-12);
    EXPECT_NEAR(b.power_W[i], r.power_W[j], 50 + 1e-9);
  }
  // The written values sit on the logger's steps: the estimate finds the resolution.
  EXPECT_NEAR(estimate_resolution(b.x_m), 1e-5, 1e-12);
  EXPECT_NEAR(estimate_resolution(b.power_W), 100, 1e-6);
}

TEST(Quantisation, ResolutionSetPointAndDitherClosedForms) {
  std::vector<double> v;
  std::mt19937 rng(4);
  std::normal_distribution<double> noise(0, 1.0);
  for (int i = 0; i < 5000; ++i) v.push_back(0.25 * std::round((10 + 3 * std::sin(0.01 * i) + noise(rng)) / 0.25));
  EXPECT_NEAR(estimate_resolution(v), 0.25, 1e-12);
  EXPECT_EQ(estimate_resolution(std::vector<double>(10, 41.9)), 0.0);
  EXPECT_FALSE(constant_within_resolution(v, 0.25));
  // A logged set point: exactly constant, or flickering over three adjacent steps (plus rare outliers).
  EXPECT_TRUE(constant_within_resolution(std::vector<double>(100, 41.9), 0.0));
  std::vector<double> sp;
  for (int i = 0; i < 1000; ++i) sp.push_back(400.0 + 0.1 * ((i % 3) - 1) + (i == 500 ? 0.5 : 0.0));
  EXPECT_TRUE(constant_within_resolution(sp, 0.1));
  sp[10] = 400.3;
  sp[20] = 400.3;
  sp[30] = 400.3;
  sp[40] = 400.3;
  sp[50] = 400.3;
  sp[60] = 400.3;
  sp[70] = 400.3;
  sp[80] = 400.3;
  sp[90] = 400.3;
  sp[95] = 400.3;
  sp[96] = 400.3;
  EXPECT_FALSE(constant_within_resolution(sp, 0.1));  // 1.1 % of the samples on a fourth step
  // q^2/12; the undithered part falls as exp(-4 pi^2 sigma^2 / q^2).
  EXPECT_NEAR(quantisation_variance(0.3), 0.0075, 1e-15);
  EXPECT_NEAR(undithered_quantisation_variance(0.3, 0.0), 0.0075, 1e-15);
  EXPECT_NEAR(undithered_quantisation_variance(1.0, 0.04), std::exp(-4 * M_PI * M_PI * 0.04) / 12, 1e-15);
  EXPECT_LT(undithered_quantisation_variance(1.0, 0.25), 1e-4 / 12);  // sigma = q/2: dithered
  EXPECT_EQ(undithered_quantisation_variance(0.0, 1.0), 0.0);
}

// The noise floor with a coarse logger and a speed channel logged at its set point: on main the set point
// got a noise floor of 1e-12 and any model speed ripple was a 5-sigma mismatch (issue 24).
TEST(Quantisation, NoiseFloorHoldsResolutionAndSetPointIsNotFitted) {
  const double w = 44.0;
  Recording model = diagtest::synthetic_run("none", 0, w, 1.0);
  ChannelHarmonics m = model_harmonics(model);
  SensorErrors e;
  e.noise_rel = 0.002;  // far below the logger's step on power: the rounding is not dithered
  e.time_offset_s = 0.013;
  e.seed = 9;
  Recording rec = apply_sensor_errors(diagtest::synthetic_run("none", 0, w, 4.0, 800.0), e);
  const double qp = 200.0;  // W, ten times the noise
  for (double& p : rec.power_W) p = qp * std::round(p / qp);
  for (double& x : rec.x_m) x = 2e-5 * std::round(x / 2e-5);
  // z swings over only +-4 steps of its logger: rounding puts a deterministic error on its low harmonics.
  const double qz = 2.5e-4;  // m
  for (double& z : rec.z_m) z = qz * std::round(z / qz);
  rec.speed_rad_s.assign(rec.size(), w);
  rec.source = "rec";
  Dataset d = prepare_dataset(rec, "rec");
  EXPECT_FALSE(d.use[kSpeed].compared);
  EXPECT_EQ(d.use[kSpeed].why_not, "set point");
  EXPECT_DOUBLE_EQ(d.use[kSpeed].setpoint_value, w);
  EXPECT_FALSE(d.use[kAx].compared);
  EXPECT_EQ(d.use[kAx].why_not, "not recorded");
  EXPECT_TRUE(d.use[kPower].compared);
  EXPECT_NEAR(d.use[kPower].resolution, qp, 1e-9);       // estimated from the data
  EXPECT_GE(d.sigma2[kPower], quantisation_variance(qp) * (1 - 1e-12));
  EXPECT_GT(d.use[kPower].quantisation_systematic, 0.1 * quantisation_variance(qp));
  EXPECT_GT(d.use[kZ].quantisation_systematic, 0.5 * quantisation_variance(qz));
  Alignment a = align(d, m);
  EXPECT_NEAR(a.tau_s, 0.013, 2e-4);
  Comparison c = compare(d, m, a, "rec");
  for (int ch = 0; ch < kNumChannels; ++ch) EXPECT_FALSE(residual_significant(c.ch[ch])) << kChannelNames[ch];
  EXPECT_FALSE(c.ch[kSpeed].compared);
  EXPECT_EQ(c.ch[kSpeed].n, 0.0);
  // A real mismatch still shows through the coarse logger: 3 % more power ripple at order 2.
  for (std::size_t i = 0; i < rec.size(); ++i) rec.power_W[i] += 9.0 * w * std::cos(2 * w * rec.t_s[i] + 0.5);
  Dataset d2 = prepare_dataset(rec, "rec");
  Comparison c2 = compare(d2, m, align(d2, m), "rec");
  EXPECT_TRUE(residual_significant(c2.ch[kPower]));
}

// Acceleration channels are compared with the model's acceleration (its displacement's second
// derivative, order by order): same alignment and the same verdict as from displacement.
TEST(Quantisation, AccelerationOnlyRecordingAlignsLikeDisplacement) {
  const double w = 41.0;
  ChannelHarmonics m = model_harmonics(diagtest::synthetic_run("none", 0, w, 1.0));
  SensorErrors e;
  e.noise_rel = 0.01;
  e.time_offset_s = 0.031;
  e.gain = 1.04;
  e.seed = 21;
  Recording rec = apply_sensor_errors(with_acceleration(diagtest::synthetic_run("none", 0, w, 3.0)), e);
  for (double& a : rec.az_m_s2) a += 9.81;  // gravity on the vertical accelerometer: a bias, not compared
  rec.x_m.clear();
  rec.y_m.clear();
  rec.z_m.clear();
  Dataset d = prepare_dataset(rec, "acc");
  Alignment a = align(d, m);
  EXPECT_NEAR(a.tau_s, 0.031, 2e-4);
  EXPECT_NEAR(a.gain, 1.04, 0.005);
  Comparison c = compare(d, m, a, "acc");
  for (int ch : {kAx, kAy, kAz, kPower}) {
    EXPECT_TRUE(c.ch[ch].compared) << kChannelNames[ch];
    EXPECT_FALSE(residual_significant(c.ch[ch])) << kChannelNames[ch] << " chi2 " << c.ch[ch].chi2;
  }
  EXPECT_FALSE(c.ch[kX].compared);
  // A model with a different motion (friction lag) is seen in the acceleration as it is in displacement.
  ChannelHarmonics wrong = model_harmonics(diagtest::synthetic_run("joint_friction", 300, w, 1.0));
  Comparison cw = compare(d, wrong, align(d, wrong), "acc");
  EXPECT_TRUE(residual_significant(cw.ch[kPower]) || residual_significant(cw.ch[kAx]));
}

// A logger sampling at a few times the drive frequency: only orders below its Nyquist limit are fitted
// (with all 12 the least-squares problem is singular and the comparison meaningless); too few samples per
// period are refused naming the rate.
TEST(Quantisation, LowSampleRateFitsOrdersBelowNyquist) {
  const double w = 41.9;  // 6.67 Hz
  ChannelHarmonics m = model_harmonics(diagtest::synthetic_run("none", 0, w, 1.0));
  SensorErrors e;
  e.noise_rel = 0.01;
  e.time_offset_s = 0.02;
  e.seed = 5;
  Recording rec = apply_sensor_errors(diagtest::synthetic_run("none", 0, w, 6.0, 80.0), e);  // 12 per period
  Dataset d = prepare_dataset(rec, "80 Hz");
  EXPECT_EQ(d.H[kX].orders(), 5);
  Alignment a = align(d, m);
  EXPECT_NEAR(a.tau_s, 0.02, 1e-3);
  Comparison c = compare(d, m, a, "80 Hz");
  for (int ch = 0; ch < kNumChannels; ++ch) EXPECT_FALSE(residual_significant(c.ch[ch])) << kChannelNames[ch];
  EXPECT_EQ(c.ch[kX].dof_chi2, 11);
  Recording slow = apply_sensor_errors(diagtest::synthetic_run("none", 0, w, 6.0, 25.0), e);  // 3.7 per period
  const std::string msg = error_of([&] { prepare_dataset(slow, "25 Hz"); });
  EXPECT_NE(msg.find("samples per drive period"), std::string::npos) << msg;
}
