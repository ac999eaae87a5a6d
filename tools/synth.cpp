// `quantum-synth`: writes a synthetic Kinect recording of an air hockey table and its truth.
#include <CLI/CLI.hpp>

#include <iostream>

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
  app.add_flag("--markers", markers, "write the four printable playfield markers into DIR instead");
  app.add_flag("--hats", hats, "write a handball hall with hatted players instead: DIR/hats.avi, DIR/accel.csv, "
                               "DIR/truth.jsonl (a 20 m x 10 m hall; --seed applies)");
  CLI11_PARSE(app, argc, argv);
  try {
    if (hats) {
      quantum::tools::HatSceneOptions h;
      h.seed = o.seed;
      const auto truth = quantum::tools::write_hat_video(dir, h);
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
