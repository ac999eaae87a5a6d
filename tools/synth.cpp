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
      ->check(CLI::Range(0.8f, 4.0f));
  app.add_option("--length", o.length, "the field's length between the markers, m")->capture_default_str()
      ->check(CLI::Range(0.2f, 5.0f));
  app.add_option("--width", o.width, "the field's width between the markers, m")->capture_default_str()
      ->check(CLI::Range(0.1f, 3.0f));
  app.add_option("--tilt", o.tilt, "degrees the camera looks off straight down (its direction drawn from --seed)")
      ->capture_default_str()->check(CLI::Range(0.0f, 15.0f));
  app.add_option("--tilt-toward", o.tilt_toward, "degrees from the red end (+x) the camera tilts toward: 0 along "
                                                 "the table, 90 across (default: drawn from --seed)")
      ->check(CLI::Range(0.0f, 360.0f));
  app.add_option("--noise", o.noise, "depth noise: standard deviation of the raw disparity, raw units")
      ->capture_default_str()->check(CLI::Range(0.0f, 10.0f));
  app.add_option("--holes", o.holes, "share of pixels without a reading, at random")->capture_default_str()
      ->check(CLI::Range(0.0f, 0.5f));
  app.add_option("--edge-dropout", o.edge_dropout, "chance that a pixel at a depth edge has no reading")
      ->capture_default_str()->check(CLI::Range(0.0f, 1.0f));
  bool no_shadow = false;
  app.add_flag("--no-shadow", no_shadow, "no projector shadow beside the arms");
  app.add_option("--speed", o.speed, "the fastest a mallet moves, m/s")->capture_default_str()
      ->check(CLI::Range(0.1f, 10.0f));
  std::vector<float> hover;
  app.add_option("--hover", hover, "LOW,HIGH: a lifted hand's height above the table, m (default 0.15,0.25)")
      ->delimiter(',')->expected(2);
  float marker_size = 0;
  app.add_option("--marker-size", marker_size, "printed side of a marker, m (default: 6.5 cm per metre of height, "
                                               "8 cm at least; with --markers: the PDF's, 0.15)");
  app.add_option("--seed", o.seed, "seed of the motion and the noise")->capture_default_str();
  bool markers = false, hats = false;
  std::string rally;
  std::vector<std::tuple<int, double, double>> away;
  app.add_flag("--markers", markers, "write the four printable playfield markers into DIR instead: PNGs and markers.pdf "
                                    "(A4, at --marker-size when printed at 100 %)");
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
  o.shadow = !no_shadow;
  o.marker_size = marker_size;
  if (!hover.empty()) o.hover_low = hover[0], o.hover_high = hover[1];
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
      quantum::tools::write_markers(dir, marker_size > 0 ? marker_size : 0.15);
      std::cout << "wrote " << dir << "/marker-0.png to marker-3.png and " << dir << "/markers.pdf\n";
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
