// make_recording: a test recording from the model with one concealed effect switched on, plus sensor
// noise, a time offset and a displacement-gain error. The effect's name is not written to the file.
//   make_recording --config BASE.yaml --effect NAME|none --value V [--noise-std R] [--time-offset-s S]
//                  [--gain G] [--seconds S] [--seed N] [--speed-rpm RPM] [--settle-s S] --out FILE.csv
// --noise-std is relative: noise std = R x channel scale (std of the channel, at least 1 % of its mean).
#include <cstdlib>
#include <iostream>
#include <string>

#include "analysis/mbd_model.hpp"
#include "analysis/sensor_model.hpp"
#include "core/cli_args.hpp"
#include "core/config.hpp"
#include "core/units.hpp"
#include "mbd/simulate.hpp"

using namespace analysis;

int main(int argc, char** argv) {
  const char* usage =
      "usage: make_recording --config BASE.yaml --effect none|joint_friction|absorber_nonlinearity|motor_droop|"
      "cardan_misalignment --value V [--noise-std R (fraction, default 0.01)] [--time-offset-s S (default 0)] "
      "[--gain G (default 1)] [--seconds S (default 10)] [--seed N (default 1)] [--speed-rpm RPM (default: "
      "config)] [--settle-s S (default 4)] --out FILE.csv\n"
      "  V in the unit of mbd.effects.<name>.<main parameter>: coulomb_Nm, cubic_N_per_m3, droop_rad_s_per_kNm, angle_deg\n";
  std::string config, effect, out;
  double value = 0, seconds = 10, speed_rpm = -1, settle = 4;
  SensorErrors e;
  e.noise_rel = 0.01;
  bool have_value = false;
  try {
    core::CliArgs args(argc, argv);
    while (args.next()) {
      const std::string a = args.flag();
      auto str = [&] { return args.value(); };
      auto num = [&](double lo, double hi) { return args.number(lo, hi); };
      if (a == "--config") config = str();
      else if (a == "--effect") effect = str();
      else if (a == "--value") { value = num(-1e15, 1e15); have_value = true; }
      else if (a == "--noise-std") e.noise_rel = num(0, 10);
      else if (a == "--time-offset-s") e.time_offset_s = num(-1e4, 1e4);
      else if (a == "--gain") e.gain = num(1e-3, 1e3);
      else if (a == "--seconds") seconds = num(0.1, 3600);
      else if (a == "--seed") e.seed = static_cast<std::uint64_t>(num(0, 1e15));
      else if (a == "--speed-rpm") speed_rpm = num(1, 5000);
      else if (a == "--settle-s") settle = num(0, 60);
      else if (a == "--out") out = str();
      else if (a == "-h" || a == "--help") { std::cout << usage; return 0; }
      else throw std::invalid_argument("unknown argument '" + a + "'");
    }
    if (config.empty() || effect.empty() || out.empty()) throw std::invalid_argument("--config, --effect and --out are required");
    if (effect != "none" && !have_value) throw std::invalid_argument("--value is required with --effect " + effect);
    mbd::MechanismParams p = mbd::load_mechanism_params_file(config);
    p = with_effect(p, effect, value);
    if (speed_rpm > 0) p = at_speed(p, speed_rpm * core::units::rpm);
    mbd::validate(p);
    mbd::SimOptions so;
    so.duration_s = seconds;
    so.settle_s = settle;
    so.load = "bed";
    Recording model = from_fields(mbd::simulate(p, so), "model");
    Recording rec = apply_sensor_errors(model, e);
    write_recording_csv(rec, out);
    std::cout << "wrote " << out << " (" << rec.size() << " samples, " << seconds << " s)\n";
    return 0;
  } catch (const std::exception& ex) {
    std::cerr << "make_recording: error: " << ex.what() << "\n" << usage;
    return 2;
  }
}
