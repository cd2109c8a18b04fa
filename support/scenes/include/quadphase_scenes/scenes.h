// SPDX-License-Identifier: MIT
// Game-like Box2D 2.4.1 worlds shared by the tests, the benchmarks and the demo.
//
// Every scene is built from (size, seed) alone and is deterministic: the same binary building the same scene
// twice and stepping it the same way gives bit-identical results. Random numbers come from std::mt19937 with
// our own portable mappings (see Rng below), never from the <random> distributions, whose output differs
// between standard libraries.
//
// The scenes only build worlds; they do not use the quadphase adapter API, so the same sources are compiled
// against both Box2D builds (quadphase::scenes and quadphase::scenes_stock). They install no contact
// listener or contact filter: those are left to the caller.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include "box2d/box2d.h"

namespace quadphase::scenes
{

enum class SceneId
{
    Pyramid, ///< size = base of a pyramid of boxes on a ground (Box2D testbed "Pyramid")
    Rain,    ///< size = circles and boxes falling into a wide open-top container
    Tumbler, ///< size = small boxes spawned into a motor-driven rotating hollow box (testbed "Tumbler")
    Tiles, ///< size = static ground tiles (10 columns per row) with a pyramid of 20 on top (testbed "Tiles")
    Particles, ///< size = circles r = 0.5 bouncing elastically in a closed box, no gravity, area fraction
               ///< 0.15
    Bullets,   ///< size = fast bullet bodies fired through thin walls at a pile, relaunched periodically
    Sparse,    ///< size = moving bodies spread thinly over a large closed world, mostly not touching
    Shooter,   ///< size = enemies chasing a player who fires streams of bullets (top-down, no gravity)
    OpenWorld, ///< size = vehicles driving through towns on a map centred ~50 km from the origin
    Mixed,     ///< size = pebbles, crates and boulders (radii 0.05-3.5 m) falling onto a 20 km static ground
    Terrain,   ///< size = circles and polygons rolling down a chain-shape landscape
    Churn,     ///< size = live bodies in a container; every step some are destroyed and as many created
};

/// Static description of a scene.
struct SceneInfo
{
    SceneId id;
    const char* name;        ///< lower-case name accepted by ParseSceneName()
    const char* description; ///< one line
    const char* sizeMeaning; ///< what `size` counts
    int minSize;
    int maxSize;
    int defaultSize;
};

/// A built world plus how to step it.
///
/// Step protocol (see StepScene()): for step = 0, 1, 2, ...
///     world->Step(timeStep, velocityIterations, positionIterations);
///     if (perStep) perStep(*world, step);
/// perStep mutates the world between steps (spawning bodies, relaunching bullets, ...). It is deterministic
/// and holds its own state; it must only be called with this scene's world and consecutive step numbers.
struct Scene
{
    SceneId id = SceneId::Pyramid;
    int size = 0;
    uint32_t seed = 0;
    std::unique_ptr<b2World> world;
    float timeStep = 1.0f / 60.0f;
    int velocityIterations = 8;
    int positionIterations = 3;
    std::function<void(b2World&, int step)> perStep; ///< may be empty
    int stepCount = 0;                               ///< steps taken through StepScene()
};

/// All scenes, in SceneId order.
const std::vector<SceneInfo>& AllScenes();

/// The description of one scene.
const SceneInfo& GetSceneInfo(SceneId id);

/// Scene name of an id ("pyramid", "rain", ...).
const char* SceneName(SceneId id);

/// Parses a scene name (case-insensitive). Returns nullopt for unknown names.
std::optional<SceneId> ParseSceneName(std::string_view name);

/// Comma-separated list of the scene names, for help and error messages.
std::string SceneNameList();

/// Builds a scene. `size` must be in [minSize, maxSize] of the scene, else std::invalid_argument is thrown.
Scene BuildScene(SceneId id, int size, uint32_t seed);

/// Convenience: only the world (for scenes without perStep, or when the caller does not need it).
std::unique_ptr<b2World> BuildSceneWorld(SceneId id, int size, uint32_t seed);

/// One step of the protocol documented at Scene: world->Step(...), then perStep(world, stepCount), then
/// ++stepCount.
void StepScene(Scene& scene);

/// Adds a body of `type` at `position` with one fixture: `shape` made of `material` (whose shape is set here).
b2Body* AddBody(b2World& world, b2BodyType type, b2Vec2 position, const b2Shape& shape,
                b2FixtureDef material);

/// Number of bodies / fixtures currently in the world (static ones included).
int32_t CountBodies(const b2World& world);
int32_t CountFixtures(const b2World& world);

/// FNV-1a hash over the bit patterns of every body's position and angle, in body-list order.
uint64_t HashBodyPositions(const b2World& world);

/// The bit patterns of every body's position, angle and velocities (x, y, angle, vx, vy, w per body), in
/// body-list order: two worlds stepped identically give equal vectors.
std::vector<uint32_t> BodyStateBits(const b2World& world);

/// Portable deterministic random numbers: std::mt19937 with explicit mappings.
class Rng
{
public:
    explicit Rng(uint32_t seed);

    uint32_t NextU32();
    /// Uniform in [0, 1): the top 24 bits of one draw, scaled by 2^-24 (exact in float).
    float Uniform01();
    /// Uniform in [lo, hi).
    float Uniform(float lo, float hi);
    /// Uniform integer in [0, n) for n > 0 (multiply-shift; bias < n / 2^32, irrelevant here).
    uint32_t Index(uint32_t n);
    /// Fisher-Yates shuffle of `values` using Index().
    void Shuffle(std::vector<int32_t>& values);

private:
    std::mt19937 m_engine;
};

} // namespace quadphase::scenes
