// SPDX-License-Identifier: MIT
// Parsing and help text of quadphase-scene's options.
#include "scene_cli_options.h"

#include <algorithm>
#include <cstdlib>
#include <map>

#include <CLI/CLI.hpp>

namespace quadphase::scene_cli
{

namespace
{

using scenes::ParseInteger;

float ParseFloat(const std::string& option, const std::string& text)
{
    // strtof: std::from_chars for float needs GCC 11+; fine here, but strtof also accepts what users type.
    char* end = nullptr;
    const float value = std::strtof(text.c_str(), &end);
    if (text.empty() || end != text.c_str() + text.size() || !(value == value) || value > 1e30f ||
        value < -1e30f)
    {
        throw UsageError("option " + option + " expects a finite number, got '" + text + "'");
    }
    return value;
}

ViewRect ParseView(const std::string& option, const std::string& text)
{
    float values[4];
    size_t start = 0;
    for (int i = 0; i < 4; ++i)
    {
        const size_t comma = text.find(',', start);
        if ((i < 3) != (comma != std::string::npos))
        {
            throw UsageError("option " + option + " expects MINX,MINY,MAXX,MAXY (four numbers), got '" +
                             text + "'");
        }
        const size_t end = i < 3 ? comma : text.size();
        values[i] = ParseFloat(option, text.substr(start, end - start));
        start = end + 1;
    }
    ViewRect view{values[0], values[1], values[2], values[3]};
    if (!(view.minX < view.maxX) || !(view.minY < view.maxY))
    {
        throw UsageError("option " + option + ": MINX must be below MAXX and MINY below MAXY, got '" + text +
                         "'");
    }
    return view;
}

std::string CheckBroadphase(const std::string& option, const std::string& value)
{
    if (value != "quadtree" && value != "stock")
    {
        throw UsageError("option " + option + " must be 'quadtree' or 'stock', got '" + value + "'");
    }
    return value;
}

bool EndsWith(const std::string& text, const std::string& suffix)
{
    return text.size() >= suffix.size() &&
           text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0;
}

/// The command line split by CLI11: the values of each value option in the order given, and the flags seen.
struct Split
{
    std::map<std::string, std::vector<std::string>> values;
    std::map<std::string, int> flags;
};

/// Splits `args` (argv without argv[0]; "--name value", "--name=value", flags) into `valueOptions` and `flags`.
/// Throws UsageError naming the option for a missing value, a flag given "=value" and, unless `othersAllowed`,
/// for anything else.
Split SplitArgs(const std::vector<std::string>& args, const std::vector<std::string>& valueOptions,
                const std::vector<std::string>& flags, bool othersAllowed)
{
    Split split;
    CLI::App app;
    app.set_help_flag();
    app.allow_extras();
    for (const std::string& name : valueOptions)
    {
        app.add_option(name, split.values[name])
            ->allow_extra_args(false)
            ->expected(1)
            ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
    }
    for (const std::string& names : flags)
    {
        app.add_flag(names, split.flags[names.substr(0, names.find(','))])->disable_flag_override();
    }
    try
    {
        app.parse(std::vector<std::string>(args.rbegin(), args.rend())); // CLI11 takes them last first
    }
    catch (const CLI::ParseError& error)
    {
        // CLI11's message does not name the option the way the tests and users expect: find it.
        for (size_t i = 0; i < args.size(); ++i)
        {
            const std::string name = args[i].substr(0, args[i].find('='));
            const bool isValueOption =
                std::find(valueOptions.begin(), valueOptions.end(), args[i]) != valueOptions.end();
            if (isValueOption && (i + 1 == args.size() || args[i + 1].rfind("--", 0) == 0))
            {
                throw UsageError("option " + args[i] + " needs a value");
            }
            if (name != args[i] && split.flags.count(name) != 0)
            {
                throw UsageError("option " + name + " takes no value");
            }
        }
        throw UsageError(error.what());
    }
    if (!othersAllowed && !app.remaining().empty())
    {
        throw UsageError("unknown option '" + app.remaining().front() + "' (see --help)");
    }
    return split;
}

} // namespace

std::string FindBroadphase(const std::vector<std::string>& args)
{
    const Split split = SplitArgs(args, {"--broadphase"}, {}, true);
    const std::vector<std::string>& given = split.values.at("--broadphase");
    return given.empty() ? "quadtree" : CheckBroadphase("--broadphase", given.back());
}

Options ParseOptions(const std::vector<std::string>& args)
{
    const Split split =
        SplitArgs(args,
                  {"--scene", "--size", "--steps", "--seed", "--broadphase", "--threads", "--png", "--every",
                   "--width", "--height", "--view", "--gif", "--mp4", "--fps"},
                  {"--help,-h", "--no-overlay", "--quiet"}, false);
    Options options;
    options.help = split.flags.at("--help") > 0;
    if (options.help)
    {
        return options;
    }
    options.overlay = split.flags.at("--no-overlay") == 0;
    options.quiet = split.flags.at("--quiet") > 0;
    bool everyGiven = false;
    for (const auto& [name, values] : split.values)
    {
        for (const std::string& value : values) // the last one wins
        {
            const auto takeValue = [&value]() {
                return value;
            };
            if (scenes::ParseSceneOption(name, takeValue, options))
            {
                // --scene, --size, --steps or --seed
            }
            else if (name == "--broadphase")
            {
                options.broadphase = CheckBroadphase(name, value);
            }
            else if (name == "--threads")
            {
                options.threads = static_cast<int>(ParseInteger(name, value, 0, 256));
            }
            else if (name == "--png")
            {
                options.pngDir = value;
                if (options.pngDir.empty())
                {
                    throw UsageError("option --png needs a directory name");
                }
            }
            else if (name == "--every")
            {
                options.every = static_cast<int>(ParseInteger(name, value, 1, 10000000));
                everyGiven = true;
            }
            else if (name == "--width" || name == "--height")
            {
                (name == "--width" ? options.width : options.height) =
                    static_cast<int>(ParseInteger(name, value, 16, 8192));
            }
            else if (name == "--view")
            {
                options.view = ParseView(name, value);
                options.autoView = false;
            }
            else if (name == "--gif" || name == "--mp4")
            {
                const std::string suffix = name == "--gif" ? ".gif" : ".mp4";
                (name == "--gif" ? options.gifPath : options.mp4Path) = value;
                if (!EndsWith(value, suffix))
                {
                    throw UsageError("option " + name + " expects a file name ending in " + suffix +
                                     ", got '" + value + "'");
                }
            }
            else if (name == "--fps")
            {
                options.fps = static_cast<int>(ParseInteger(name, value, 1, 120));
            }
        }
    }

    scenes::ResolveSceneSize(options.sceneId, options.size);
    if (options.threads >= 0 && options.broadphase != "quadtree")
    {
        throw UsageError(
            "--threads sets the quadtree's pair-generation threads: it needs --broadphase quadtree");
    }
    if ((!options.gifPath.empty() || !options.mp4Path.empty()) && options.pngDir.empty())
    {
        throw UsageError("--gif and --mp4 are made from the PNG frames: give --png DIR too");
    }
    if (everyGiven && options.pngDir.empty())
    {
        throw UsageError("--every sets how often --png writes a frame: give --png DIR too");
    }
    return options;
}

std::string HelpText(const char* program)
{
    std::string text = std::string("usage: ") + program + R"( [options]

Steps one scene of quadphase's scene library with the quadtree broadphase or with Box2D's stock
b2DynamicTree, prints a one-line summary per second of simulated time and, with --png, renders frames
(bodies, and in the quadtree build the quadtree's occupied cells) and optionally a GIF or MP4 (ffmpeg).

options:
  --scene NAME          scene to step (default rain); see the list below
  --size N              scene size (default: the scene's default; ranges below)
  --steps N             steps to take, 1/60 s each (default 600)
  --seed N              scene seed, 0..4294967295 (default 1)
  --broadphase KIND     quadtree (default): Box2D 2.4.1 with quadphase's quadtree (quadphase::box2d);
                        stock: untouched Box2D 2.4.1 (no quadtree, so no overlay)
  --threads N           quadtree only: pair-generation threads, 0..256 (quadphase::Config::threads; 1: no
                        thread is started). Without it the world keeps the library's default, 0: up to
                        OMP_NUM_THREADS, else the cores, but parallel only in scenes of 16,384 proxies or
                        more and only while parallel calls measure faster than serial ones
  --png DIR             write frames DIR/frame_00000.png, ... (DIR is created if missing); the first
                        frame shows the world before the first step
  --every N             with --png: a frame every N steps (default 10)
  --width W, --height H frame size in pixels, 16..8192 (default 800 x 600)
  --view MINX,MINY,MAXX,MAXY
                        world rectangle to draw, metres (default: the bounds of the bodies at the start,
                        leaving out fixtures more than 2 km across, such as mixed's ground)
  --no-overlay          do not draw the quadtree's cells
  --gif FILE.gif        after the run, make an animated GIF of the frames with ffmpeg (needs --png)
  --mp4 FILE.mp4        after the run, make an H.264 MP4 of the frames with ffmpeg (needs --png)
  --fps N               animation frames per second, 1..120 (default 30)
  --quiet               no per-second summary lines (the final summary is still printed)
  --help, -h            this text

The per-second line: simulated time, bodies, awake bodies, contacts, new pairs in that second (pairs that
reached Box2D's contact filter: the same count in both builds) and the mean broadphase milliseconds per step
(b2Profile::broadphase: synchronising proxies and finding new pairs).

Overlay: every occupied quadtree cell is filled with its level's colour, more opaque the more proxies it
holds (relative to the fullest cell); the legend lists the levels in use with their occupied cells.

Exit status: 0 on success, 1 on a run-time failure (cannot write a frame, ffmpeg failed), 2 on bad options.

scenes:
)";
    for (const scenes::SceneInfo& info : scenes::AllScenes())
    {
        std::string name = info.name;
        name.resize(11, ' ');
        text += "  " + name + info.description + "\n";
        text += "             size = " + std::string(info.sizeMeaning) + ", " + std::to_string(info.minSize) +
                ".." + std::to_string(info.maxSize) + ", default " + std::to_string(info.defaultSize) + "\n";
    }
    return text;
}

} // namespace quadphase::scene_cli
