// Kicks and rolling: on a field with height and friction (a pitch), a ball rolling on the floor
// slows as e^(-kt) and stops, a ball in the air flies its arc unslowed, and the prediction knows
// both. The field is the basketball half court (rules/basketball/field.lua) given friction.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <map>

#include "test_scenes.h"

namespace quantum {
namespace {

constexpr float kDt = 1.0f / 60;
constexpr float kFriction = 0.5f;

Field pitch() {
  Field f = test::quiet("basketball");
  f.friction = kFriction;
  return f;
}

TEST(Rolling, ABallRollingOnTheFloorSlowsAndStopsWhereFrictionSays) {
  const Field f = pitch();
  World world(f, WorldConfig{.particles = 1});
  const std::vector<BodyInput> in = test::parked_in_corner(f);
  world.place_bodies(in);
  const float x0 = -5, v0 = 2.5f;
  world.set_cloud(test::one_ball({x0, 8, f.ball_radius}, {v0, 0, 0}));
  std::vector<Event> events;
  for (int s = 1; s <= 600; ++s) {
    world.step(kDt, in, events);
    const float t = float(s) * kDt;
    ASSERT_NEAR(world.cloud().x[0], x0 + v0 / kFriction * (1 - std::exp(-kFriction * t)), 1e-3f) << "at " << t << " s";
    ASSERT_NEAR(world.cloud().vx[0], v0 * std::exp(-kFriction * t), 1e-4f) << "at " << t << " s";
    ASSERT_EQ(world.cloud().z[0], f.ball_radius);
  }
  // Ten seconds on it is e^-5 of its speed and as far from where it stops.
  EXPECT_NEAR(world.cloud().x[0], x0 + v0 / kFriction, v0 / kFriction * std::exp(-10 * kFriction) + 1e-3f);
  EXPECT_TRUE(events.empty());
}

// A lofted ball lands, bounces lower each time, then rolls and stops: the prediction of 20 s
// says where, as the step does. A player standing a little short of that place gets it; one a
// little beyond does not.
TEST(Rolling, PredictionKnowsWhereALoftedBallRollsToAStop) {
  const Field f = pitch();
  const int maya = test::body_named(f, "Maya");
  const float reach = f.bodies[size_t(maya)].radius + f.ball_radius;
  // Where it stops, found by stepping alone with nobody near.
  World alone(f, WorldConfig{.particles = 1});
  std::vector<BodyInput> in = test::parked_in_corner(f);
  alone.place_bodies(in);
  const Vec3 from{-6, 7, 0.5f}, kick{1.5f, 0, 3};
  alone.set_cloud(test::one_ball(from, kick));
  std::vector<Event> events;
  for (int s = 0; s < 60 * 20; ++s) alone.step(kDt, in, events);
  const float stops = alone.cloud().x[0];
  EXPECT_NEAR(alone.cloud().y[0], from.y, 1e-4f);
  EXPECT_LT(std::hypot(alone.cloud().vx[0], alone.cloud().vz[0]), 0.01f) << "stopped";
  EXPECT_EQ(alone.cloud().z[0], f.ball_radius) << "on the floor";
  // Bouncing at 1.5 m/s for under 4 s, then rolling less than 1.5 / k = 3 m.
  EXPECT_GT(stops - from.x, 3.0f);
  EXPECT_LT(stops - from.x, 1.5f * 4 + 1.5f / kFriction);
  for (const float margin : {-0.1f, 0.1f}) {
    in = test::parked_in_corner(f, {{"Maya", {stops + margin + reach, from.y}}});
    World world(f, WorldConfig{.particles = 1});
    world.place_bodies(in);
    world.set_cloud(test::one_ball(from, kick));
    const FateReport report = world.predict(20.0f);
    ASSERT_EQ(report.groups.size(), 1u);
    const bool reaches = margin < 0;
    EXPECT_EQ(report.groups[0].fate.kind, reaches ? FateKind::Catch : FateKind::Field) << "margin " << margin;
    events.clear();
    for (int s = 0; s < 60 * 20; ++s) world.step(kDt, in, events);
    bool caught = false;
    for (const Event& e : events) caught = caught || e.type == EventType::Catch || e.type == EventType::Pickup;
    EXPECT_EQ(caught, reaches) << "margin " << margin;
  }
}

// Each particle of a spread of kicks, along the ground and lofted, stepped alone, meets what the
// prediction said it would: a player, the line, or nothing (it stops on the court).
TEST(Rolling, RollingParticlesArePredictedAndSteppedAlike) {
  const Field f = pitch();
  const std::vector<BodyInput> in = test::parked_in_corner(f, {{"Maya", {1, 9}}, {"Pia", {-2, 4}}});
  Cloud all;
  for (int i = 0; i < 240; ++i) {
    const float heading = -2.2f + 2.4f * float(i % 24) / 23, speed = 1.5f + 4.5f * float(i / 24) / 9;
    const float up = i % 3 == 0 ? 0.0f : i % 3 == 1 ? 1.5f : 4.0f;
    all.push(Vec3{-4, 9, f.ball_radius}, Vec3{speed * std::cos(heading), speed * std::sin(heading), up}, 1, 1);
  }
  World whole(f, WorldConfig{.particles = uint32_t(all.size())});
  whole.place_bodies(in);
  whole.set_cloud(all);
  const FateReport report = whole.predict(30.0f);
  std::map<std::string, int> seen;
  for (size_t i = 0; i < all.size(); ++i) {
    Cloud one;
    one.push_from(all, i);
    World world(f, WorldConfig{.particles = 1});
    world.place_bodies(in);
    world.set_cloud(one);
    std::vector<Event> events;
    for (int s = 0; s < 60 * 30 && !std::any_of(events.begin(), events.end(), [](const Event& e) {
                                     return e.type != EventType::Bounce;
                                   });
         ++s)
      world.step(kDt, in, events);
    std::string stepped = "stays in field";
    for (const Event& e : events)
      if (e.type == EventType::Out) stepped = "out";
      else if (e.type == EventType::Catch) stepped = "caught by " + f.bodies[size_t(e.actor)].name;
    const Fate& fate = report.groups[report.group_of[i]].fate;
    std::string predicted = describe(fate, f);
    predicted = predicted.substr(0, predicted.find(" via"));
    ASSERT_EQ(predicted, stepped) << "particle " << i;
    ++seen[stepped];
  }
  for (const auto& [what, n] : seen) std::cout << what << ": " << n << '\n';
  EXPECT_GE(seen["caught by Maya"], 5);
  EXPECT_GE(seen["caught by Pia"], 5);
  EXPECT_GE(seen["out"], 20);
  EXPECT_GE(seen["stays in field"], 20);
}

// A kick along the ground starts every particle on the floor, rolling: none is scattered upward,
// and friction slows each as e^(-kt).
TEST(Kick, AlongTheGroundEveryParticleRollsFromTheFeet) {
  const Field f = pitch();
  const int maya = test::body_named(f, "Maya");
  const std::vector<BodyInput> in = test::parked_in_corner(f, {{"Maya", {-4, 8}}});
  World world(f, WorldConfig{.particles = 500});
  world.place_bodies(in);
  world.give(maya);
  std::vector<Event> events;
  world.release(maya, {4, 0, 0}, ThrowSpread{0.05f, 0.1f, 0.05f}, events, World::Release::Kick);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].type, EventType::Kick);
  EXPECT_STREQ(to_string(events[0].type), "kick");
  const Cloud start = world.cloud();
  ASSERT_EQ(start.size(), 500u);
  for (size_t i = 0; i < start.size(); ++i) {
    ASSERT_EQ(start.z[i], f.ball_radius) << "particle " << i;
    ASSERT_EQ(start.vz[i], 0.0f) << "particle " << i;
  }
  events.clear();
  for (int s = 0; s < 60; ++s) world.step(kDt, in, events);
  const Cloud& later = world.cloud();
  for (size_t i = 0; i < later.size(); ++i) ASSERT_EQ(later.z[i], f.ball_radius) << "particle " << i;
  double speed = 0, was = 0;
  for (size_t i = 0; i < later.size(); ++i) speed += later.w[i] * std::hypot(later.vx[i], later.vy[i]);
  for (size_t i = 0; i < start.size(); ++i) was += start.w[i] * std::hypot(start.vx[i], start.vy[i]);
  EXPECT_NEAR(speed / was, std::exp(-kFriction * 1.0), 0.01) << "a second of rolling";
}

// A lofted kick leaves the floor at the kick's angle, scattered; a particle scattered below the
// horizontal rolls instead of going into the floor.
TEST(Kick, ALoftedKickLeavesTheFloorAndNoneGoesIntoIt) {
  const Field f = pitch();
  const int maya = test::body_named(f, "Maya");
  const std::vector<BodyInput> in = test::parked_in_corner(f, {{"Maya", {-4, 8}}});
  World world(f, WorldConfig{.particles = 2000});
  world.place_bodies(in);
  world.give(maya);
  std::vector<Event> events;
  const float elevation = 0.1f;  // rad: about 6 degrees, with a spread of 0.1 rad
  world.release(maya, {5 * std::cos(elevation), 0, 5 * std::sin(elevation)}, ThrowSpread{0.05f, 0.1f, 0.1f}, events,
                World::Release::Kick);
  const Cloud& c = world.cloud();
  int rolling = 0;
  for (size_t i = 0; i < c.size(); ++i) {
    ASSERT_EQ(c.z[i], f.ball_radius) << "particle " << i;
    ASSERT_GE(c.vz[i], 0.0f) << "particle " << i;
    rolling += c.vz[i] == 0;
  }
  // One standard deviation below the horizontal: P(N < -1) = 0.159 of 2,000, binomial SD 16.
  EXPECT_NEAR(rolling, 0.159 * 2000, 4 * 16);
}

// On a flat field a kick goes as a throw: the same particles from the same seed, told as a kick.
TEST(Kick, OnAFlatFieldAKickIsAThrowFromTheFeet) {
  const Field f = test::quiet("handball");
  const int ben = test::body_named(f, "Ben");
  std::vector<BodyInput> in;
  for (size_t k = 0; k < f.bodies.size(); ++k) in.push_back({{-8.0f + 0.5f * float(k), -8}, {0, 0}});
  in[size_t(ben)] = {{-3, 2}, {0, 0}};
  Cloud clouds[2];
  for (const World::Release how : {World::Release::Throw, World::Release::Kick}) {
    World world(f, WorldConfig{.particles = 100});
    world.place_bodies(in);
    world.give(ben);
    std::vector<Event> events;
    world.release(ben, {6, 1, 0}, ThrowSpread{0.06f, 0.1f}, events, how);
    EXPECT_EQ(events.at(0).type, how == World::Release::Kick ? EventType::Kick : EventType::Throw);
    clouds[how == World::Release::Kick] = world.cloud();
  }
  EXPECT_EQ(clouds[0].x, clouds[1].x);
  EXPECT_EQ(clouds[0].vx, clouds[1].vx);
  EXPECT_EQ(clouds[0].vy, clouds[1].vy);
}

// A body that kicks holds the ball at its feet: it must catch, and the field says which one is
// wrong.
TEST(Kick, ABodyThatKicksMustCatch) {
  Field f = pitch();
  f.bodies[1].kicks = true;
  World fine(f, WorldConfig{});
  f.bodies[1].catches = false;
  try {
    World world(f, WorldConfig{});
    ADD_FAILURE() << "a body that kicks but does not catch was taken";
  } catch (const FieldError& e) {
    EXPECT_EQ(e.place, "bodies[2] (" + f.bodies[1].name + ")");
    EXPECT_NE(e.message.find("must catch"), std::string::npos) << e.message;
  }
}

}  // namespace
}  // namespace quantum
