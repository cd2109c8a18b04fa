// SPDX-License-Identifier: MIT
// A C++11 game file that includes every installed header (Box2D's, and quadphase's public ones: <quadphase/box2d.h>
// and the core headers it stands on), built with -std=c++11 -Wall -Wextra -Wpedantic -Werror and linked to
// quadphase's libbox2d.so.2 (abi_cxx11_consumer): the headers are C++11, and every extra they declare
// (tests/abi/quadphase_exports.txt) is exported by the library (hidden visibility by default) and works.
// Exit status 1 on a failed check.
#include <box2d/box2d.h>

#include "cxx11_consumer_headers.h" // generated: #include of every installed quadphase header

#include <cstdio>
#include <cstring>

namespace
{

int g_failures = 0;
int g_unknownProxyReports = 0;

void Check(bool ok, const char* what)
{
    if (!ok)
    {
        ++g_failures;
        std::printf("check failed: %s\n", what);
    }
}

void CountReports(quadphase::ErrorCode code, const char* message, void* context)
{
    Check(context == &g_unknownProxyReports, "the handler gets its context back");
    Check(message != nullptr && message[0] != '\0', "the report has a message");
    if (code == quadphase::ErrorCode::UnknownProxy)
    {
        ++g_unknownProxyReports;
    }
}

// The error hook and validation of a b2BroadPhase used on its own.
void CheckBroadPhaseExtras()
{
    const quadphase::ErrorHandler previous =
        quadphase::SetErrorHandler(&CountReports, &g_unknownProxyReports);
    const bool wasStrict = quadphase::SetStrictErrors(false);
    b2BroadPhase broadPhase;
    quadphase::SetValidation(broadPhase, true);
    Check(quadphase::IsValidating(broadPhase), "SetValidation(b2BroadPhase&) switches validation on");
    b2AABB box;
    box.lowerBound.Set(0.0f, 0.0f);
    box.upperBound.Set(1.0f, 1.0f);
    const int32 a = broadPhase.CreateProxy(box, nullptr);
    box.lowerBound.Set(0.5f, 0.5f);
    box.upperBound.Set(1.5f, 1.5f);
    broadPhase.CreateProxy(box, nullptr);
    broadPhase.DestroyProxy(a + 100); // an unknown id: reported through the handler
    struct NoPairs
    {
        void AddPair(void*, void*) {}
    } noPairs;
    broadPhase.UpdatePairs(&noPairs);
    const quadphase::ValidationReport report = quadphase::GetValidationReport(broadPhase);
    Check(report.checks == 1 && report.mismatches == 0, "one UpdatePairs checked, no mismatch");
    Check(g_unknownProxyReports == 1, "the installed handler got the unknown id");
    Check(std::strcmp(quadphase::ErrorCodeName(quadphase::ErrorCode::UnknownProxy), "unknown proxy") == 0,
          "ErrorCodeName names the code");
    quadphase::SetStrictErrors(wasStrict);
    quadphase::SetErrorHandler(previous);
}

} // namespace

int main()
{
    CheckBroadPhaseExtras();

    b2World world(b2Vec2(0.0f, -10.0f));
    quadphase::Config config = quadphase::GetConfig(world);
    config.depth = 5;
    quadphase::Configure(world, config);
    quadphase::SetTaskSystem(world, quadphase::TaskSystem()); // OpenMP, as by default
    quadphase::SetValidation(world, true);
    quadphase::SetTiming(world, true);
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
    const quadphase::Stats stats = quadphase::GetStats(world);
    const quadphase::ValidationReport report = quadphase::GetValidationReport(world);
    std::printf("depth %d proxies %d UpdatePairs %lld checks %lld mismatches %lld\n", stats.depth,
                int(stats.proxyCount), static_cast<long long>(stats.updatePairsCalls),
                static_cast<long long>(report.checks), static_cast<long long>(report.mismatches));
    Check(stats.depth == 5 && quadphase::GetConfig(world).depth == 5, "Configure's depth is the one in use");
    Check(stats.proxyCount == 21, "21 proxies");
    // Box2D calls UpdatePairs once per step, and again after time-of-impact events.
    Check(report.checks >= 60 && report.mismatches == 0, "validation checked every step, no mismatch");
    Check(stats.updatePairsCalls == report.checks,
          "validation checked every UpdatePairs the statistics count");
    Check(stats.updateSeconds > 0.0, "SetTiming timed the proxy updates");
    quadphase::ResetCounters(world);
    Check(quadphase::GetStats(world).updatePairsCalls == 0, "ResetCounters zeroes the work counters");
    return g_failures == 0 ? 0 : 1;
}
