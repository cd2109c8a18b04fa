// A C++11 game file that includes every installed header (Box2D's, quadphase's core and adapter headers, among them
// <quadphase/box2d.h>, the extras), built with -std=c++11 -Wall -Wextra -Wpedantic -Werror and linked to
// quadphase's libbox2d.so.2 (abi_cxx11_consumer): the headers are C++11, and the extras they declare are exported
// by the library (hidden visibility by default) and work. Exit status 1 on a failed check.
#include <box2d/box2d.h>

#include "cxx11_consumer_headers.h" // generated: #include of every installed quadphase header

#include <cstdio>

namespace
{

int g_failures = 0;

void Check(bool ok, const char* what)
{
    if (!ok)
    {
        ++g_failures;
        std::printf("check failed: %s\n", what);
    }
}

} // namespace

int main()
{
    b2World world(b2Vec2(0.0f, -10.0f));
    quadphase::Config config = quadphase::GetConfig(world);
    config.depth = 5;
    quadphase::Configure(world, config);
    quadphase::SetValidation(world, true);
    quadphase::Trace trace;
    quadphase::SetTrace(world, &trace);
    b2BodyDef ground;
    b2Body* body = world.CreateBody(&ground);
    b2EdgeShape edge;
    edge.SetTwoSided(b2Vec2(-20.0f, 0.0f), b2Vec2(20.0f, 0.0f));
    body->CreateFixture(&edge, 0.0f);
    for (int i = 0; i < 20; ++i)
    {
        b2BodyDef def;
        def.type = b2_dynamicBody;
        def.position.Set(-10.0f + float(i), 1.0f + 0.1f * float(i));
        b2PolygonShape box;
        box.SetAsBox(0.4f, 0.4f);
        world.CreateBody(&def)->CreateFixture(&box, 1.0f);
    }
    for (int step = 0; step < 60; ++step)
    {
        world.Step(1.0f / 60.0f, 8, 3);
    }
    quadphase::SetTrace(world, nullptr);
    const quadphase::Stats stats = quadphase::GetStats(world);
    const quadphase::ValidationReport report = quadphase::GetValidationReport(world);
    const quadphase::QuadtreeBroadPhase& tree = quadphase::GetQuadtree(world);
    std::printf("depth %d proxies %d checks %lld mismatches %lld trace ops %zu\n", stats.depth,
                int(stats.proxyCount), static_cast<long long>(report.checks),
                static_cast<long long>(report.mismatches), trace.Ops().size());
    Check(stats.depth == 5, "Configure's depth is the one GetStats reports");
    Check(stats.proxyCount == 21 && tree.GetProxyCount() == 21, "21 proxies");
    // Box2D calls UpdatePairs once per step, and again after time-of-impact events.
    Check(report.checks >= 60 && report.mismatches == 0, "validation checked every step, no mismatch");
    Check(trace.UpdatePairsCount() == report.checks,
          "the trace recorded every UpdatePairs validation checked");
    return g_failures == 0 ? 0 : 1;
}
