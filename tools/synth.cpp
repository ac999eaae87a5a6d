// `quantum-synth`: writes a synthetic Kinect recording of an air hockey table, or a video of a
// handball hall, and its truth.
#include <CLI/CLI.hpp>

#include <iostream>

#include "field_loader.h"
#include "synthetic.h"

int main(int argc, char** argv) {
  CLI::App app{"Write a synthetic Kinect recording (libfreenect's record format) of two players at an air hockey "
               "table, with the ground truth in DIR/truth.jsonl"};
  quantum::tools::DepthSceneOptions o;
  std::string dir;
  app.add_option("DIR", dir, "the recording's directory (created)")->required();
  app.add_option("--frames", o.frames, "frames with the players, after the empty-table ones")->capture_default_str();
  app.add_option("--background-frames", o.background_frames, "frames of the empty table first")->capture_default_str();
  app.add_option("--height", o.height, "the camera's height above the table, m")->capture_default_str()
      ->check(CLI::Range(0.8f, 2.0f));
  app.add_option("--length", o.length, "the field's length between the markers, m")->capture_default_str();
  app.add_option("--width", o.width, "the field's width between the markers, m")->capture_default_str();
  app.add_option("--seed", o.seed, "seed of the motion and the noise")->capture_default_str();
  bool markers = false, hats = false;
  std::string rally;
  std::vector<std::tuple<int, double, double>> away;
  app.add_flag("--markers", markers, "write the four printable playfield markers into DIR instead");
  auto* hats_flag = app.add_flag("--hats", hats, "write a handball hall with hatted players instead: DIR/hats.avi, "
                                                 "DIR/accel.csv, DIR/truth.jsonl (a 20 m x 10 m hall; --seed applies)");
  app.add_option("--rally", rally, "with --hats: a rally on the hall of FIELD (rules/handball) from the match's start, "
                                   "two passes and a goal, with DIR/truth.json")
      ->needs(hats_flag);
  app.add_option("--away", away, "with --hats: player K is off the hall from FROM to TO s (FROM 0: walks in at TO); "
                                 "K counts blue 0-2 then red 3-5, or a rally's field bodies")
      ->delimiter(',')
      ->needs(hats_flag);
  CLI11_PARSE(app, argc, argv);
  try {
    if (hats) {
      quantum::tools::HatSceneOptions h;
      h.seed = o.seed;
      for (const auto& [player, from, to] : away) h.away.push_back({player, from, to});
      const auto truth = rally.empty() ? quantum::tools::write_hat_video(dir, h)
                                       : quantum::tools::write_rally_video(dir, h, quantum::lua::load_field(rally));
      std::cout << "wrote " << truth.frames.size() << " frames to " << dir << "/hats.avi\n";
      return 0;
    }
    if (markers) {
      quantum::tools::write_markers(dir);
      std::cout << "wrote " << dir << "/marker-0.png to marker-3.png\n";
      return 0;
    }
    const auto truth = quantum::tools::write_depth_recording(dir, o);
    std::cout << "wrote " << truth.size() << " depth frames to " << dir << '\n';
  } catch (const std::exception& e) {
    std::cerr << "quantum-synth: " << e.what() << '\n';
    return 1;
  }
  return 0;
}
