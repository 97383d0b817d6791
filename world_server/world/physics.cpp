// Bullet (double precision, single-threaded) for the arena. Why it is set up as it is
// (measured on this machine):
//  - robots are DYNAMIC btCylinderShapeZ bodies: kinematic bodies get no contacts;
//  - gravity zero, linear factor (1,1,0), angular factor (0,0,1): planar, no tipping, no z drift;
//  - DISABLE_DEACTIVATION: a sleeping body would ignore the velocities we set;
//  - velocities are re-set from the wheel speeds before EVERY substep, so a push by a neighbour or a wall
//    lasts one substep and the robot then drives as its wheels say (a wheeled robot does not coast);
//  - friction 0 between all bodies: a robot pressed against a wall or a neighbour slides along it instead of
//    being stuck or spun by contact friction (its heading is the wheels' business);
//  - bodies added in a fixed order: static bodies, then robots by id.
#include "world_server/world/physics.hpp"

#include <BulletCollision/CollisionDispatch/btSimulationIslandManager.h>
#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <utility>
#include <vector>

#include "world_server/world/geometry.hpp"

namespace swarmform::world {
namespace {

constexpr double kTouching = 0.0005;  // m: a manifold point this close (or penetrating) is a contact
constexpr std::uint64_t kStaticFlag = 1ULL << 63;

double yaw_of(const btTransform& t) {
  const btQuaternion q = t.getRotation();
  return wrap_angle(
      fast_atan2(2.0 * (q.w() * q.z() + q.x() * q.y()), 1.0 - 2.0 * (q.y() * q.y() + q.z() * q.z())));
}

// btDiscreteDynamicsWorld without the per-body work our planar robots do not need:
//  - predictUnconstraintMotion is skipped: it applies damping (zero, with two pow() calls per body) and
//    predicts a transform that only continuous collision detection and motion states read;
//  - createPredictiveContacts is skipped: it predicts every body again, for CCD only. Continuous collision
//    detection is off (dispatch info m_useContinuous = false): at 10 ms substeps discrete contacts do not
//    tunnel up to 3 m/s (tests/world/physics_test.cpp drives at 1 m/s into a 2 cm
//    wall);
//  - solveConstraints hands the solver only the contact manifolds, without Bullet's island pass over every
//    body (btSimulationIslandManager::buildAndProcessIslands sorts all N bodies by island each substep, then
//    batches every island, lone robots included, into the solver, which copies a lone robot's velocities
//    into a solver body and back unchanged: ~6,000 instructions per robot and tick for nothing). The
//    manifolds are those Bullet would solve, in the order Bullet solves them: the same list (dispatcher
//    order, filtered by needsResponse) sorted by the same predicate with the same btAlignedObjectArray
//    quickSort, using the island tags calculateSimulationIslands stored (kept). Islands do not interact
//    in the solver, so one solveGroup over them all equals Bullet's batches of islands;
//  - step_once is stepSimulation(dt, 0) without what it adds around the one internal step for other worlds
//    (each a loop over every body): saving kinematic states (none here), applying gravity (zero: adds
//    exactly 0 to forces that are 0), motion states (none), clearing forces (still 0), profiling;
//  - updateActivationState does nothing: every moving body is DISABLE_DEACTIVATION (make_dynamic_flags), for
//    which Bullet's loop changes nothing;
//  - integrateTransforms does what Bullet's integrateTransformsInternal does for a body that moves in the
//    plane and turns about z only (integrate_planar below), and calls `after_integrate` on each body right
//    after its integration (Physics re-sets the velocities of the next substep from the wheels there: the
//    body's new heading is known, and it is still in cache). The physics stays on one thread: measured,
//    integrating slices of the bodies on the worker pool made the physics slower (1.9 -> 2.7 ms a tick at
//    N = 1000), as every substep then moves each body's state from core to core and back for ~250 ns of
//    work on it.
class PlanarDynamicsWorld : public btDiscreteDynamicsWorld {
 public:
  using btDiscreteDynamicsWorld::btDiscreteDynamicsWorld;

  // One internal step of dt (what stepSimulation(dt, 0) does in this world, see above).
  void step_once(btScalar dt) { internalSingleStepSimulation(dt); }

  // Called on each non-static body right after its integration (null: nothing).
  std::function<void(btRigidBody& body)> after_integrate;
  // By robot (user index): the cosine and sine of the angle it turns in one substep of this tick.
  std::vector<std::pair<double, double>> turn;

 protected:
  void predictUnconstraintMotion(btScalar) override {}
  void createPredictiveContacts(btScalar) override { releasePredictiveContacts(); }
  void updateActivationState(btScalar) override {}

  void integrateTransforms(btScalar dt) override {
    for (int i = 0; i < m_nonStaticRigidBodies.size(); ++i) {
      btRigidBody& body = *m_nonStaticRigidBodies[i];
      integrate_planar(body, dt);
      if (after_integrate) after_integrate(body);
    }
  }

  // Bullet's integration of one body (btTransformUtil::integrateTransform, then proceedToTransform) for our
  // bodies, which move in the plane and turn about z only (linear factor (1,1,0), angular factor (0,0,1)).
  // The origin moves by v dt, computed as Bullet computes it. The basis turns by the substep's angle w dt,
  // `turn` (its cosine and sine, by the body's user index), as a rotation of its first two columns: where
  // Bullet converts the basis to a quaternion, builds the exponential map of w dt with a sine and a cosine,
  // multiplies, renormalises and converts back, which is the same rotation up to rounding (half of the
  // serial physics time at N = 1000, BENCHMARKS.md). One Newton step keeps the columns' length at 1 as
  // Bullet's renormalisation does. What proceedToTransform also does is left out: the interpolation
  // transforms and velocities, which only motion states and continuous collision detection read (neither is
  // used here), and the world inertia tensor, zero for bodies with no inertia.
  void integrate_planar(btRigidBody& body, btScalar dt) const {
    body.setHitFraction(1.0);
    btTransform& t = body.getWorldTransform();
    t.setOrigin(t.getOrigin() + body.getLinearVelocity() * dt);
    const auto& [c_turn, s_turn] = turn[static_cast<std::size_t>(body.getUserIndex())];
    btMatrix3x3& r = t.getBasis();
    const double c = r[0][0] * c_turn - r[1][0] * s_turn;
    const double s = r[1][0] * c_turn + r[0][0] * s_turn;
    const double k = 1.5 - 0.5 * (c * c + s * s);
    r.setValue(c * k, -s * k, 0.0, s * k, c * k, 0.0, 0.0, 0.0, 1.0);
  }

  void solveConstraints(btContactSolverInfo& info) override {
    btDispatcher* dispatcher = getDispatcher();
    // btSimulationIslandManager::buildIslands's list (no kinematic bodies here, so nothing to wake).
    manifolds_.resize(0);
    const int count = dispatcher->getNumManifolds();
    for (int i = 0; i < count; ++i) {
      btPersistentManifold* m = dispatcher->getManifoldByIndexInternal(i);
      const btCollisionObject* a = m->getBody0();
      const btCollisionObject* b = m->getBody1();
      if (a->getActivationState() == ISLAND_SLEEPING && b->getActivationState() == ISLAND_SLEEPING) continue;
      if (dispatcher->needsResponse(a, b)) manifolds_.push_back(m);
    }
    // btSimulationIslandManager::processIslands's order (m_deterministicOverlappingPairs is off).
    manifolds_.quickSort(ByIsland());
    // The moving bodies the manifolds touch (static ones are the solver's fixed body).
    bodies_.resize(0);
    in_bodies_.assign(static_cast<std::size_t>(getNumCollisionObjects()), 0);
    for (int i = 0; i < manifolds_.size(); ++i) {
      for (const btCollisionObject* o : {manifolds_[i]->getBody0(), manifolds_[i]->getBody1()}) {
        const auto k = static_cast<std::size_t>(o->getWorldArrayIndex());
        if (o->isStaticOrKinematicObject() || in_bodies_[k]) continue;
        in_bodies_[k] = 1;
        bodies_.push_back(const_cast<btCollisionObject*>(o));
      }
    }
    m_constraintSolver->prepareSolve(getNumCollisionObjects(), dispatcher->getNumManifolds());
    if (manifolds_.size() > 0) {
      m_constraintSolver->solveGroup(bodies_.size() > 0 ? &bodies_[0] : nullptr, bodies_.size(),
                                     &manifolds_[0], manifolds_.size(), nullptr, 0, info, getDebugDrawer(),
                                     dispatcher);
    }
    m_constraintSolver->allSolved(info, getDebugDrawer());
  }

 private:
  // btSimulationIslandManager.cpp's btPersistentManifoldSortPredicate.
  struct ByIsland {
    static int island(const btPersistentManifold* m) {
      return m->getBody0()->getIslandTag() >= 0 ? m->getBody0()->getIslandTag()
                                                : m->getBody1()->getIslandTag();
    }
    bool operator()(const btPersistentManifold* a, const btPersistentManifold* b) const {
      return island(a) < island(b);
    }
  };
  btAlignedObjectArray<btPersistentManifold*> manifolds_;
  btAlignedObjectArray<btCollisionObject*> bodies_;
  std::vector<char> in_bodies_;  // by world array index: already in bodies_
};

}  // namespace

struct Physics::Impl {
  // Bullet's world and what it points at; destroyed in reverse order.
  btDefaultCollisionConfiguration config;
  btCollisionDispatcher dispatcher{&config};
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  PlanarDynamicsWorld dyn{&dispatcher, &broadphase, &solver, &config};

  btCylinderShapeZ robot_shape{btVector3(kRobotRadius, kRobotRadius, kRobotHeight / 2.0)};
  btVector3 robot_inertia{0, 0, 0};
  std::vector<std::unique_ptr<btCollisionShape>> static_shapes;
  std::vector<std::unique_ptr<btRigidBody>> statics;
  std::vector<std::unique_ptr<btRigidBody>> robots;

  struct Wheels {
    double left = 0.0, right = 0.0;
  };
  std::vector<Wheels> wheels;
  std::vector<double> v, w;  // this tick's linear (m/s) and angular (rad/s) body velocities, by robot
  std::vector<char> dead;
  double substep_s = 0.01;
  int substeps = 10;

  // Contact pairs touching during this tick and the previous one (sorted keys), and this tick's onsets.
  std::vector<std::uint64_t> touching, touching_prev;
  std::uint32_t onsets_rr = 0, onsets_ro = 0;

  std::vector<char> static_in_world;  // per static body: in the dynamics world (an absent obstacle is not)

  ~Impl() {
    for (auto& b : robots) dyn.removeRigidBody(b.get());
    for (std::size_t k = 0; k < statics.size(); ++k) {
      if (static_in_world[k]) dyn.removeRigidBody(statics[k].get());
    }
  }

  static btTransform static_transform(const Obstacle& o) {
    btTransform t;
    t.setIdentity();
    t.setOrigin(btVector3(o.centre.x, o.centre.y, kStaticHeight / 2.0));
    t.setRotation(btQuaternion(btVector3(0, 0, 1), o.yaw));
    return t;
  }

  void add_static(const Obstacle& o, int index) {
    std::unique_ptr<btCollisionShape> shape;
    if (o.kind == Obstacle::Kind::Box) {
      shape =
          std::make_unique<btBoxShape>(btVector3(o.half_extents.x, o.half_extents.y, kStaticHeight / 2.0));
    } else {
      shape = std::make_unique<btCylinderShapeZ>(btVector3(o.radius, o.radius, kStaticHeight / 2.0));
    }
    btRigidBody::btRigidBodyConstructionInfo info(0.0, nullptr, shape.get());
    info.m_startWorldTransform = static_transform(o);
    info.m_friction = 0.0;
    info.m_restitution = 0.0;
    auto body = std::make_unique<btRigidBody>(info);
    body->setUserIndex(-1);
    body->setUserIndex2(index);
    dyn.addRigidBody(body.get());
    static_shapes.push_back(std::move(shape));
    statics.push_back(std::move(body));
    static_in_world.push_back(1);
  }

  void add_robot(const Pose2D& p, RobotId id) {
    btTransform t;
    t.setIdentity();
    t.setOrigin(btVector3(p.x, p.y, kRobotHeight / 2.0));
    t.setRotation(btQuaternion(btVector3(0, 0, 1), p.theta));
    btRigidBody::btRigidBodyConstructionInfo info(kRobotMass, nullptr, &robot_shape, robot_inertia);
    info.m_startWorldTransform = t;
    info.m_friction = 0.0;
    info.m_restitution = 0.0;
    info.m_linearDamping = 0.0;
    info.m_angularDamping = 0.0;
    auto body = std::make_unique<btRigidBody>(info);
    make_dynamic_flags(*body);
    body->setUserIndex(static_cast<int>(id));
    dyn.addRigidBody(body.get());
    robots.push_back(std::move(body));
  }

  static void make_dynamic_flags(btRigidBody& b) {
    b.setLinearFactor(btVector3(1, 1, 0));
    b.setAngularFactor(btVector3(0, 0, 1));
    b.forceActivationState(DISABLE_DEACTIVATION);
    // A cylinder spinning about its axis has no gyroscopic torque; skip Bullet's (costly) implicit term.
    b.setFlags(b.getFlags() & ~BT_ENABLE_GYROSCOPIC_FORCE_IMPLICIT_BODY);
  }

  // The body velocities for the wheel speeds of this tick (differential drive: v = (l+r)/2 along the heading,
  // w = (r-l)/wheel_spacing), from the body's heading now. v and w are the same for every substep of a tick.
  // The heading's direction is the body's x axis, the first column of its rotation (cos, sin of the yaw for
  // a body turning about z only): no atan2, sin or cos per body and substep.
  void apply_wheels(btRigidBody& b, std::size_t i) const {
    if (dead[i]) return;
    const btMatrix3x3& r = b.getWorldTransform().getBasis();
    b.setLinearVelocity(btVector3(v[i] * r[0][0], v[i] * r[1][0], 0.0));
    b.setAngularVelocity(btVector3(0.0, 0.0, w[i]));
  }

  // v and w of every robot for this tick, from the wheel speeds set by set_wheels.
  // Also each robot's turn in one substep, for the world's planar integration.
  void wheels_to_velocities() {
    v.resize(wheels.size());
    w.resize(wheels.size());
    dyn.turn.resize(wheels.size());
    for (std::size_t i = 0; i < wheels.size(); ++i) {
      v[i] = 0.5 * (wheels[i].left + wheels[i].right);
      w[i] = (wheels[i].right - wheels[i].left) / kWheelSpacing;
      dyn.turn[i] = {std::cos(w[i] * substep_s), std::sin(w[i] * substep_s)};
    }
  }

  // Adds the pairs touching now to `touching` (unsorted; deduplicated at the end of the tick).
  void collect_contacts() {
    const int n = dispatcher.getNumManifolds();
    for (int m = 0; m < n; ++m) {
      const btPersistentManifold* man = dispatcher.getManifoldByIndexInternal(m);
      bool touch = false;
      for (int c = 0; c < man->getNumContacts() && !touch; ++c)
        touch = man->getContactPoint(c).getDistance() < kTouching;
      if (!touch) continue;
      const btCollisionObject* a = man->getBody0();
      const btCollisionObject* b = man->getBody1();
      int ra = a->getUserIndex(), rb = b->getUserIndex();
      if (ra < 0 && rb < 0) continue;  // static-static: never
      if (ra >= 0 && rb >= 0) {
        if (ra > rb) std::swap(ra, rb);
        touching.push_back((static_cast<std::uint64_t>(ra) << 32) | static_cast<std::uint32_t>(rb));
      } else {
        const int robot = ra >= 0 ? ra : rb;
        const int obstacle = ra >= 0 ? b->getUserIndex2() : a->getUserIndex2();
        touching.push_back(kStaticFlag | (static_cast<std::uint64_t>(robot) << 32) |
                           static_cast<std::uint32_t>(obstacle));
      }
    }
  }

  void count_onsets() {
    std::sort(touching.begin(), touching.end());
    touching.erase(std::unique(touching.begin(), touching.end()), touching.end());
    onsets_rr = onsets_ro = 0;
    for (std::uint64_t key : touching) {
      if (std::binary_search(touching_prev.begin(), touching_prev.end(), key)) continue;
      if (key & kStaticFlag) {
        ++onsets_ro;
      } else {
        const auto a = static_cast<std::size_t>(key >> 32);
        const auto b = static_cast<std::size_t>(key & 0xffffffffULL);
        (dead[a] || dead[b]) ? ++onsets_ro : ++onsets_rr;
      }
    }
    std::swap(touching, touching_prev);
    touching.clear();
  }
};

Physics::Physics(const Scenario& s) : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.dyn.setGravity(btVector3(0, 0, 0));
  m.dyn.getDispatchInfo().m_useContinuous = false;
  m.robot_shape.calculateLocalInertia(kRobotMass, m.robot_inertia);
  m.substeps = s.substeps;
  m.substep_s = 1.0 / (s.tick_rate * static_cast<double>(s.substeps));
  const std::vector<Obstacle> obstacles = static_obstacles(s);
  for (std::size_t k = 0; k < obstacles.size(); ++k) m.add_static(obstacles[k], static_cast<int>(k));
  for (std::size_t k = 0; k < obstacles.size(); ++k) {
    if (!obstacles[k].present) set_obstacle(k, obstacles[k]);  // absent at tick 0: out of the world
  }
  m.robots.reserve(s.robots.size());
  for (std::size_t i = 0; i < s.robots.size(); ++i) m.add_robot(s.robots[i], static_cast<RobotId>(i));
  m.wheels.assign(s.robots.size(), {});
  m.dead.assign(s.robots.size(), 0);
}

Physics::~Physics() = default;

void Physics::set_wheels(RobotId id, double left, double right) {
  impl_->wheels[id] = {left, right};
}

void Physics::stop_wheel(RobotId id, int side) {
  (side == 0 ? impl_->wheels[id].left : impl_->wheels[id].right) = 0.0;
}

// Substep k's velocities are set from each body's heading at the start of substep k: before the first
// substep here, and for the next ones right after the body's integration in the previous substep (the last
// thing that moves a body within a substep; PlanarDynamicsWorld::integrateTransforms).
void Physics::tick_forward() {
  Impl& m = *impl_;
  m.wheels_to_velocities();
  for (std::size_t i = 0; i < m.robots.size(); ++i) m.apply_wheels(*m.robots[i], i);
  const auto next_substep = [&m](btRigidBody& b) {
    m.apply_wheels(b, static_cast<std::size_t>(b.getUserIndex()));
  };
  for (int k = 0; k < m.substeps; ++k) {
    m.dyn.after_integrate = k + 1 < m.substeps ? std::function(next_substep) : nullptr;
    m.dyn.step_once(m.substep_s);  // stepSimulation(substep_s, 0): exactly one internal step
    m.collect_contacts();
  }
  m.dyn.after_integrate = nullptr;
  m.count_onsets();
}

void Physics::read_poses(std::vector<Pose2D>& out) const {
  out.resize(impl_->robots.size());
  for (std::size_t i = 0; i < impl_->robots.size(); ++i) {
    const btTransform& t = impl_->robots[i]->getWorldTransform();
    out[i] = Pose2D{t.getOrigin().x(), t.getOrigin().y(), yaw_of(t)};
  }
}

Pose2D Physics::pose(RobotId id) const {
  const btTransform& t = impl_->robots[id]->getWorldTransform();
  return Pose2D{t.getOrigin().x(), t.getOrigin().y(), yaw_of(t)};
}

void Physics::set_dead(RobotId id, bool dead) {
  Impl& m = *impl_;
  if (static_cast<bool>(m.dead[id]) == dead) return;
  btRigidBody& b = *m.robots[id];
  m.dyn.removeRigidBody(&b);
  b.setLinearVelocity(btVector3(0, 0, 0));
  b.setAngularVelocity(btVector3(0, 0, 0));
  b.clearForces();
  if (dead) {
    b.setMassProps(0.0, btVector3(0, 0, 0));
    b.setCollisionFlags(b.getCollisionFlags() | btCollisionObject::CF_STATIC_OBJECT);
  } else {
    b.setCollisionFlags(b.getCollisionFlags() & ~btCollisionObject::CF_STATIC_OBJECT);
    b.setMassProps(kRobotMass, m.robot_inertia);
  }
  b.updateInertiaTensor();
  m.dyn.addRigidBody(&b);
  if (!dead) Impl::make_dynamic_flags(b);
  m.wheels[id] = {};
  m.dead[id] = dead ? 1 : 0;
}

std::uint32_t Physics::onsets_robot_robot() const {
  return impl_->onsets_rr;
}
std::uint32_t Physics::onsets_robot_obstacle() const {
  return impl_->onsets_ro;
}

void Physics::set_obstacle(std::size_t index, const Obstacle& o) {
  Impl& m = *impl_;
  btRigidBody& body = *m.statics.at(index);
  body.setWorldTransform(Impl::static_transform(o));
  if (o.present && !m.static_in_world[index]) {
    m.dyn.addRigidBody(&body);
    m.static_in_world[index] = 1;
  } else if (!o.present && m.static_in_world[index]) {
    m.dyn.removeRigidBody(&body);
    m.static_in_world[index] = 0;
  }
  if (o.present) m.dyn.updateSingleAabb(&body);
}

}  // namespace swarmform::world
