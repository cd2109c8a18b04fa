// SPDX-License-Identifier: MIT
// caveexpress-physics: plays CaveExpress maps headless through the game's own server code and reports the
// time of each b2World::Step.
//
// It is built inside CaveExpress 2.5.2's own CMake build (scripts/real-game.sh injects it with
// examples/real_game/physics_driver.cmake) and links the game's static server libraries, so the physics it
// runs is the game's: caveexpress::Map loads a map from base/caveexpress/maps, spawns its entities, NPCs and
// a player, and calls b2World::Step(1/60 s, 8, 3) from Map::update exactly as the dedicated server does. The
// driver only advances the clock 1 ms per call, the same way the game's own MapTest does, and reads b2World's
// profile after each call. It compiles against whichever <box2d.h> the build found (stock or quadphase) and
// never names quadphase: under QUADPHASE_VALIDATE=1 the library itself checks every UpdatePairs.
//
// Run it from the game's source root (the data is read from base/caveexpress/):
//   caveexpress-physics [--seconds S] [--seed N] MAP...
// Output, one line per map (tab-separated, after a "map" tag):
//   map NAME steps SIMULATED_S median_step_ms p90_step_ms mean_step_ms median_broadphase_ms median_tick_ms
//       bodies contacts proxies reloads p99_broadphase_ms max_broadphase_ms total_broadphase_ms p99_step_ms
//       max_step_ms total_step_ms
// (p99 and max are what a player sees as a hitch; the totals are what the run cost.)
// Exit status 0 when every map loaded and stepped, 1 otherwise, 2 on bad arguments.

#include "caveexpress/main/CaveExpress.h"
#include "caveexpress/server/entities/Player.h"
#include "caveexpress/server/map/Map.h"
#include "common/Application.h"
#include "common/ConfigManager.h"
#include "common/EventHandler.h"
#include "common/IConsole.h"
#include "common/Log.h"
#include "common/SpriteDefinition.h"
#include "common/TextureDefinition.h"
#include "game/GameRegistry.h"
#include "network/INetwork.h"
#include "service/ServiceProvider.h"
#include "tests/TestFrontend.h"

#include <box2d.h>

#include <SDL.h>
#include <SDL_main.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace
{

// Swallows the game's log: the driver's output is its result lines.
class QuietConsole : public IConsole
{
    void init(IFrontend*) override {}
    void logInfo(const std::string&) override {}
    void logError(const std::string& text) override
    {
        std::fprintf(stderr, "caveexpress: %s\n", text.c_str());
    }
    void logDebug(const std::string&) override {}
    void render() override {}
    void update(uint32_t) override {}
};

double Mean(const std::vector<double>& values)
{
    double sum = 0.0;
    for (double v : values)
    {
        sum += v;
    }
    return values.empty() ? 0.0 : sum / static_cast<double>(values.size());
}

double Quantile(std::vector<double> values, double q)
{
    if (values.empty())
    {
        return 0.0;
    }
    std::sort(values.begin(), values.end());
    const size_t index = static_cast<size_t>(q * static_cast<double>(values.size() - 1) + 0.5);
    return values[index];
}

// Loads the map, adds one player (client id 1, 3 lives) and starts it, as MapTest::testSuccess does.
bool StartMap(caveexpress::CaveExpress& game, const std::string& name)
{
    if (!game.mapLoad(name))
    {
        return false;
    }
    caveexpress::Map& map = game.getMap();
    caveexpress::Player* player = new caveexpress::Player(map, 1); // the map owns its players
    player->setLives(3);
    if (!map.initPlayer(player))
    {
        delete player;
        return false;
    }
    map.startMap();
    return map.isActive() && map.getWorld() != nullptr;
}

struct MapResult
{
    // b2Profile::step of each b2World::Step (Box2D's own timer, compiled in the library).
    std::vector<double> stepMs;
    // b2Profile::broadphase of each step: b2ContactManager::FindNewContacts, i.e. UpdatePairs.
    std::vector<double> broadphaseMs;
    // Wall time of the game update that contained the step (the game's logic and the step).
    std::vector<double> tickMs;
    // Times the map failed or was won and was loaded again.
    int reloads = 0;
};

// Plays one map for `seconds` simulated seconds: the clock advances 1 ms per update, so an update performs at
// most one b2World::Step (every 16.7 ms of game time). A step is detected by a sentinel written into the
// world's profile before the update; b2World::Step overwrites the whole profile.
bool PlayMap(caveexpress::CaveExpress& game, const std::string& name, int seconds, MapResult& result)
{
    if (!StartMap(game, name))
    {
        std::fprintf(stderr, "caveexpress-physics: could not load and start map '%s'\n", name.c_str());
        return false;
    }
    const int steps = seconds * 60;
    int guard = seconds * 1000 * 4; // generous bound on updates (warm-up, reload delays)
    while (static_cast<int>(result.stepMs.size()) < steps)
    {
        if (--guard < 0)
        {
            std::fprintf(stderr, "caveexpress-physics: map '%s' stopped stepping after %zu steps\n",
                         name.c_str(), result.stepMs.size());
            return false;
        }
        caveexpress::Map& map = game.getMap();
        b2World* world = map.getWorld();
        b2Profile& profile = const_cast<b2Profile&>(world->GetProfile());
        profile.step = -1.0f;
        const auto start = std::chrono::steady_clock::now();
        game.update(1);
        const auto end = std::chrono::steady_clock::now();
        if (map.getWorld() == world && world->GetProfile().step >= 0.0f)
        {
            result.stepMs.push_back(world->GetProfile().step);
            result.broadphaseMs.push_back(world->GetProfile().broadphase);
            result.tickMs.push_back(std::chrono::duration<double, std::milli>(end - start).count());
        }
        if (map.isFailed() || map.isDone())
        {
            ++result.reloads;
            if (!StartMap(game, name))
            {
                std::fprintf(stderr, "caveexpress-physics: could not reload map '%s'\n", name.c_str());
                return false;
            }
        }
    }
    return true;
}

int Usage(const char* argv0, int status)
{
    std::fprintf(
        status == 0 ? stdout : stderr,
        "usage: %s [--seconds S] [--seed N] MAP...\n"
        "  plays each CaveExpress map headless for S simulated seconds (default 60) at the game's 60 Hz\n"
        "  physics rate; run from the game's source root. rand() is seeded with N (default 1) per map.\n",
        argv0);
    return status;
}

} // namespace

extern "C" int main(int argc, char* argv[])
{
    long seconds = 60;
    long seed = 1;
    std::vector<std::string> maps;
    for (int i = 1; i < argc; ++i)
    {
        const std::string arg = argv[i];
        if ((arg == "--seconds" || arg == "--seed") && i + 1 < argc)
        {
            char* end = nullptr;
            const long value = std::strtol(argv[++i], &end, 10);
            if (end == argv[i] || *end != '\0' || value < (arg == "--seconds" ? 1 : 0) || value > 86400)
            {
                std::fprintf(stderr, "caveexpress-physics: bad value '%s' for %s\n", argv[i], arg.c_str());
                return 2;
            }
            (arg == "--seconds" ? seconds : seed) = value;
        }
        else if (arg == "--help" || arg == "-h")
        {
            return Usage(argv[0], 0);
        }
        else if (!arg.empty() && arg[0] == '-')
        {
            std::fprintf(stderr, "caveexpress-physics: unknown option '%s'\n", arg.c_str());
            return Usage(argv[0], 2);
        }
        else
        {
            maps.push_back(arg);
        }
    }
    if (maps.empty())
    {
        return Usage(argv[0], 2);
    }

    // The same start-up as the game's test runner (src/tests/TestAll.cpp and AbstractTest::SetUp): the game
    // registered by CaveExpress.cpp, its data under base/caveexpress/, a frontend that draws nothing, and the
    // loopback network with the server side open (CaveExpress::update only runs the map on a server).
    QuietConsole console;
    Application& app = Singleton<Application>::getInstance();
    const GamePtr& registered = Singleton<GameRegistry>::getInstance().getGame();
    app.setOrganisation("caveproductions");
    app.setName(registered->getName());
    Log::get().addConsole(&console);
    SDL_LogSetPriority(SDL_LOG_CATEGORY_APPLICATION, SDL_LOG_PRIORITY_CRITICAL);
    char* configArgv[] = {argv[0], nullptr};
    Config.init(nullptr, 1, configArgv);

    TestFrontend frontend;
    EventHandler eventHandler;
    ServiceProvider serviceProvider;
    serviceProvider.init(&frontend, &eventHandler);
    serviceProvider.updateNetwork(false);
    serviceProvider.getNetwork().openServer(12345, nullptr);
    caveexpress::CaveExpress game;
    game.init(&frontend, serviceProvider);
    TextureDefinition textures("small");
    SpriteDefinition::get().init(textures);

    int status = 0;
    for (const std::string& name : maps)
    {
        std::srand(static_cast<unsigned>(seed));
        MapResult result;
        if (!PlayMap(game, name, static_cast<int>(seconds), result))
        {
            status = 1;
            continue;
        }
        b2World* world = game.getMap().getWorld();
        const double steps = static_cast<double>(result.stepMs.size());
        std::printf("map\t%s\t%zu\t%.3f\t%.4f\t%.4f\t%.4f\t%.4f\t%.4f\t%d\t%d\t%d\t%d\t%.4f\t%.4f\t%.3f\t%."
                    "4f\t%.4f\t%.3f\n",
                    name.c_str(), result.stepMs.size(), steps / 60.0, Quantile(result.stepMs, 0.5),
                    Quantile(result.stepMs, 0.9), Mean(result.stepMs), Quantile(result.broadphaseMs, 0.5),
                    Quantile(result.tickMs, 0.5), world->GetBodyCount(), world->GetContactCount(),
                    world->GetProxyCount(), result.reloads, Quantile(result.broadphaseMs, 0.99),
                    Quantile(result.broadphaseMs, 1.0), Mean(result.broadphaseMs) * steps,
                    Quantile(result.stepMs, 0.99), Quantile(result.stepMs, 1.0), Mean(result.stepMs) * steps);
        std::fflush(stdout);
        game.mapShutdown();
    }
    game.shutdown();
    serviceProvider.shutdown();
    Config.shutdown();
    return status;
}
