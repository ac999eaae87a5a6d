// Synthetic recordings for the tracking tests: a Kinect above an air hockey table with the four
// playfield markers, two players reaching in over the short ends with mallets (some lifted,
// hovering), rendered by ray casting into libfreenect's record format with Kinect-like disparity
// quantization, noise and holes, plus the ground truth; and a handball hall filmed from its
// ceiling with hatted players and their accelerometers. `quantum-synth` writes them from the
// command line.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "quantum/field.h"

namespace quantum::tools {

struct DepthSceneOptions {
  // A small table, so that from 1.0 m up a Kinect's 57 x 44 degrees see it whole, markers included.
  float length = 0.9f, width = 0.45f;  // the field between the markers' centres, m
  float height = 1.3f;                 // the camera above the table, m
  float tilt = 1.0f;                   // degrees the camera looks off straight down ...
  float tilt_toward = -1;              // ... toward this many degrees from the red end (+x; 90: across); < 0: drawn from the seed
  float offset = 0.02f;                // m: and stands this far off the table's centre, at most
  float marker_size = 0;               // m, printed side of a marker; 0: the set-up guide's, 6.5 cm per metre of height (8 cm at least)
  int background_frames = 30;         // empty table first, for the background
  int frames = 300;                   // then this many with the players
  double fps = 30;
  double hover_share = 0.3;           // of the play frames, roughly, each hand is lifted
  float hover_low = 0.15f, hover_high = 0.25f;  // m: a lifted hand's height above the table (its centre)
  float speed = 2.0f;                 // m/s: the fastest a mallet moves
  float noise = 0.5f;                 // standard deviation of the raw disparity, in raw units
  float holes = 0.01f;                // share of pixels with no reading, plus a few hole blobs
  bool shadow = true;                 // no reading where the projector (7.5 cm beside the camera) is hidden by an arm
  float edge_dropout = 0.5f;          // chance that a pixel at a depth edge (> 3 cm step) has no reading
  int blind_columns = 8;              // the Kinect v1's left columns that never give depth
  int colour_every = 15;              // a colour frame every this many depth frames
  uint64_t seed = 1;
  std::string blue = "Blue's mallet", red = "Red's mallet";  // the players' ids in the truth

  float printed_marker_size() const;  // marker_size, or the guide's for this height
};

struct TruthPlayer {
  std::string id;
  double x = 0, y = 0;  // the mallet's centre on the table, field metres
  bool hovering = false;
  double hand = 0;      // depth scenes: the hand's height above the table (its centre), m
};

struct TruthFrame {
  int frame = 0;  // depth frames counted from 0, the background's included
  double t = 0;
  std::vector<TruthPlayer> players;  // empty during the background
};

// Writes the four playfield markers as printable PNGs, dir/marker-<id>.png, each captioned with
// the corner it goes on, and as dir/markers.pdf: one A4 page a marker, `side` metres a side when
// printed at 100 % (a 10 cm bar on each page checks it), with ticks that point at its centre.
void write_markers(const std::string& dir, double side = 0.15);

// Writes the recording into `dir` (INDEX.txt and the frames) and the truth into
// dir/truth.jsonl, one JSON object per depth frame; returns the truth.
std::vector<TruthFrame> write_depth_recording(const std::string& dir, const DepthSceneOptions& options);

// A handball hall seen from the ceiling: the four markers on its corners, players in coloured
// hats (blue and red), their throws in their accelerometer samples.
struct HatSceneOptions {
  float length = 20.0f, width = 10.0f;  // the hall's field between the markers' centres, m
  float height = 13.0f;                 // the camera above the floor, m
  float horizontal_fov = 82;            // degrees
  int image_width = 1280, image_height = 720;
  float marker_size = 0.6f;             // m
  float hat_height = 1.8f, hat_radius = 0.13f;  // m
  double seconds = 10, fps = 30;
  uint64_t seed = 1;
  // A player off the hall for a while: the scene's player `player` (write_hat_video's: blue 0-2,
  // red 3-5; a rally's: the field's bodies, in order) jogs out over the nearer side line from
  // `from` and is back on its way at `to`. From 0 or before: they walk in at `to`.
  struct Away {
    int player = 0;
    double from = 0, to = 0;
  };
  std::vector<Away> away;
};

struct TruthThrow {
  double t = 0;
  std::string player;
  double dx = 0, dy = 0;  // the thrower's direction of motion
  std::string to;         // in a rally: the teammate it is aimed at ("" for a shot at goal)
};

struct HatTruth {
  std::vector<TruthFrame> frames;  // the hats in the picture: x, y under the hat, never hovering
  std::vector<TruthThrow> throws;
};

// Six players, three a team, two of each crossing paths at the clip's middle, the third walking
// a circle; four throws. Ids are the tracker's: the team and a number by x at the first frame,
// players who walk in later numbered on in the order they come. Writes dir/hats.avi (MJPG),
// dir/accel.csv (t,player,ax,ay,az at 100 Hz) and dir/truth.jsonl.
HatTruth write_hat_video(const std::string& dir, const HatSceneOptions& options);

// A rally of handball on `hall` (rules/handball's default field: 20 m x 10 m, three a side,
// goalkeepers), from the match's start: every player at their place, the ball with Blue's field
// player nearest the centre (match.start = "blue"), who passes to her teammate running up the
// wing; he passes back, and she scores in Red's goal, its goalkeeper come out to her side.
// Every throw is made on the run, straight at its target. Writes what write_hat_video does and
// dir/truth.json: the throws (time, thrower's track id and name, and the teammate it is aimed at
// or the goal) and the goal's scorer. Throws std::invalid_argument for another hall.
HatTruth write_rally_video(const std::string& dir, const HatSceneOptions& options, const Field& hall);

}  // namespace quantum::tools
