#include "box2d_backend.h"

#include <box2d/box2d.h>

#include <cmath>
#include <optional>

#include "quantum/noise.h"

namespace quantum {
namespace {

constexpr uint16_t kSolid = 0x0001;     // walls and bodies
constexpr uint16_t kParticle = 0x0002;  // collide with solids, never with each other
constexpr uintptr_t kBodyTag = uintptr_t(1) << 40;  // particles are 1..n, bodies kBodyTag + k
constexpr uintptr_t kWallTag = uintptr_t(1) << 41;  // walls kWallTag + w

// Box2D edges carry a skin of b2_polygonRadius. Shrinking the particle by it keeps wall contact
// at the ball's radius; growing bodies by it keeps body contact there too.
constexpr float kSkin = b2_polygonRadius;

// A wall or body: frictionless, bouncing at every speed (Box2D's default threshold of 1 m/s
// would stop slow bounces that the fast core keeps).
b2FixtureDef solid(const b2Shape* shape, float restitution, uintptr_t tag) {
  b2FixtureDef fd;
  fd.shape = shape;
  fd.friction = 0;
  fd.restitution = restitution;
  fd.restitutionThreshold = 0;
  fd.filter.categoryBits = kSolid;
  fd.userData.pointer = tag;
  return fd;
}

// Which particle first touched which body, and which wall it first bounced off audibly, during
// one Step. Box2D reports a contact before solving it, so the particle's velocity is the approach.
class FirstContacts final : public b2ContactListener {
 public:
  std::vector<int32_t>* body = nullptr;  // per particle: body index or -1
  std::vector<int32_t>* wall = nullptr;  // per particle: wall index or -1
  float audible = 0;

  void BeginContact(b2Contact* c) override {
    b2Fixture *fa = c->GetFixtureA(), *fb = c->GetFixtureB();
    b2WorldManifold m;
    c->GetWorldManifold(&m);
    record(fa, fb, m.normal);
    record(fb, fa, -m.normal);
  }

 private:
  // `normal` points from `particle` to `other`.
  void record(b2Fixture* particle, b2Fixture* other, b2Vec2 normal) {
    const uintptr_t p = particle->GetUserData().pointer, o = other->GetUserData().pointer;
    if (p == 0 || p >= kBodyTag) return;
    if (o >= kWallTag) {
      int32_t& slot = (*wall)[p - 1];
      if (slot < 0 && b2Dot(particle->GetBody()->GetLinearVelocity(), normal) > audible) slot = int32_t(o - kWallTag);
    } else if (o >= kBodyTag) {
      int32_t& slot = (*body)[p - 1];
      if (slot < 0) slot = int32_t(o - kBodyTag);
    }
  }
};

// Whether the straight move p->q crosses goal line a-b toward the side away from `inside`.
bool crosses(Vec2 p, Vec2 q, const Goal& g, Vec2 inside) {
  const float ex = g.b.x - g.a.x, ey = g.b.y - g.a.y;
  auto side = [&](Vec2 s) { return ex * (s.y - g.a.y) - ey * (s.x - g.a.x); };
  const float sp = side(p), sq = side(q), si = side(inside);
  if (sp * si < 0 || sq * si > 0 || sp == sq) return false;  // must go from the field side to the goal side
  const float t = sp / (sp - sq);
  const float along = ((p.x + t * (q.x - p.x) - g.a.x) * ex + (p.y + t * (q.y - p.y) - g.a.y) * ey) / (ex * ex + ey * ey);
  return along >= 0 && along <= 1;
}

class Box2DBackend final : public Backend {
 public:
  explicit Box2DBackend(const Field& field) : field_(field), world_(b2Vec2(0, 0)) {
    world_.SetAllowSleeping(false);
    world_.SetContactListener(&listener_);
    b2BodyDef ground_def;
    b2Body* ground = world_.CreateBody(&ground_def);
    for (const Segment& s : field.segments) {
      b2EdgeShape edge;
      edge.SetTwoSided(b2Vec2(s.a.x, s.a.y), b2Vec2(s.b.x, s.b.y));
      const b2FixtureDef fd = solid(&edge, field.wall_restitution, kWallTag + s.wall);
      ground->CreateFixture(&fd);
    }
    for (size_t k = 0; k < field.bodies.size(); ++k) {
      b2BodyDef bd;
      bd.type = b2_kinematicBody;
      bd.position.Set(field.bodies[k].start.x, field.bodies[k].start.y);
      b2Body* body = world_.CreateBody(&bd);
      b2CircleShape circle;
      circle.m_radius = field.bodies[k].radius + kSkin;
      const b2FixtureDef fd = solid(&circle, field.body_restitution, kBodyTag + k);
      body->CreateFixture(&fd);
      bodies_.push_back(body);
    }
    for (const Spot& s : field.spots) inside_.x += s.at.x / field.spots.size(), inside_.y += s.at.y / field.spots.size();
  }

  void advance(Cloud& cloud, const StepContext& ctx, std::vector<Contact>& contacts) override {
    const size_t n = cloud.size();
    while (particles_.size() < n) add_particle();
    while (particles_.size() > n) {
      world_.DestroyBody(particles_.back());
      particles_.pop_back();
    }
    mirrored_.resize(n, Mirror{NAN, NAN, NAN, NAN});
    for (int k = 0; k < ctx.n_bodies; ++k) {
      const BodyMotion& m = ctx.bodies[k];
      bodies_[k]->SetTransform(b2Vec2(m.from.x, m.from.y), 0);
      bodies_[k]->SetLinearVelocity(b2Vec2((m.to.x - m.from.x) / ctx.dt, (m.to.y - m.from.y) / ctx.dt));
      if (bodies_[k]->IsEnabled() == m.passes) bodies_[k]->SetEnabled(!m.passes);
    }
    start_.resize(n);
    for (size_t i = 0; i < n; ++i) {
      float dx = 0, dy = 0;
      if (ctx.noise_amplitude > 0) noise_offsets(noise_bits(uint32_t(i), ctx.noise_key), ctx.noise_amplitude, dx, dy);
      start_[i] = {cloud.x[i] + dx, cloud.y[i] + dy};
      // Teleporting a body makes Box2D re-pair it in the broadphase: only do it when the engine
      // changed the particle (split, removal, realized shot) or Brownian motion moved it.
      const Mirror& seen = mirrored_[i];
      if (dx != 0 || dy != 0 || seen.x != cloud.x[i] || seen.y != cloud.y[i])
        particles_[i]->SetTransform(b2Vec2(start_[i].x, start_[i].y), 0);
      if (seen.vx != cloud.vx[i] || seen.vy != cloud.vy[i])
        particles_[i]->SetLinearVelocity(b2Vec2(cloud.vx[i], cloud.vy[i]));
    }
    first_body_.assign(n, -1);
    first_wall_.assign(n, -1);
    listener_.body = &first_body_;
    listener_.wall = &first_wall_;
    listener_.audible = field_.audible_bounce;
    world_.Step(ctx.dt, 8, 3);
    const int ng = int(field_.goals.size());
    for (size_t i = 0; i < n; ++i) {
      const b2Vec2 p = particles_[i]->GetPosition(), v = particles_[i]->GetLinearVelocity();
      cloud.x[i] = p.x, cloud.y[i] = p.y, cloud.vx[i] = v.x, cloud.vy[i] = v.y;
      mirrored_[i] = {p.x, p.y, v.x, v.y};
      // The first thing met, in the fast backend's order of precedence: body, goal, out, wall.
      std::optional<Target> met;
      if (first_body_[i] >= 0) met = Target{TargetKind::Body, uint16_t(first_body_[i])};
      for (int g = 0; g < ng && !met; ++g)
        if (crosses(start_[i], {p.x, p.y}, field_.goals[g], inside_)) met = Target{TargetKind::Goal, uint16_t(g)};
      if (!met && (p.x < field_.bounds_min.x || p.x > field_.bounds_max.x || p.y < field_.bounds_min.y ||
                   p.y > field_.bounds_max.y))
        met = Target{TargetKind::Out, 0};
      if (!met && first_wall_[i] >= 0) met = Target{TargetKind::Wall, uint16_t(first_wall_[i])};
      if (met) contacts.push_back({uint32_t(i), *met});
    }
  }

  void set_wormholes(const std::vector<Wormhole>& wormholes) override {
    if (!wormholes.empty()) throw std::logic_error("the Box2D reference has no wormholes");
  }

 private:
  void add_particle() {
    b2BodyDef bd;
    bd.type = b2_dynamicBody;
    bd.fixedRotation = true;
    b2Body* body = world_.CreateBody(&bd);
    b2CircleShape circle;
    circle.m_radius = field_.ball_radius - kSkin;
    b2FixtureDef fd;
    fd.shape = &circle;
    fd.density = 1;
    fd.friction = 0;
    fd.restitution = 0;  // Box2D mixes restitution by max: the wall's or body's value applies
    fd.restitutionThreshold = 0;
    fd.filter.categoryBits = kParticle;
    fd.filter.maskBits = kSolid;
    fd.userData.pointer = particles_.size() + 1;
    body->CreateFixture(&fd);
    particles_.push_back(body);
  }

  Field field_;
  b2World world_;
  FirstContacts listener_;
  std::vector<b2Body*> particles_, bodies_;
  struct Mirror {
    float x, y, vx, vy;  // what Box2D holds for the particle, as last copied into the cloud
  };
  std::vector<Mirror> mirrored_;
  std::vector<Vec2> start_;
  std::vector<int32_t> first_body_, first_wall_;
  Vec2 inside_;
};

}  // namespace

std::unique_ptr<Backend> make_box2d_backend(const Field& field) {
  if (field.has_height()) throw FieldError("gravity", "the Box2D reference replays flat fields only");
  if (field.ball_radius <= kSkin)
    throw FieldError("ball.radius", "the Box2D reference needs a ball radius above its skin of " +
                                        std::to_string(kSkin) + " m");
  return std::make_unique<Box2DBackend>(field);
}

}  // namespace quantum
