// SPDX-License-Identifier: MIT
// Starts ffmpeg with posix_spawnp (no shell: paths are passed as they are).
#include "animation.h"

#include <spawn.h>
#include <sys/wait.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <vector>

extern char** environ;

namespace quadphase::scene_cli
{

std::string FrameFileName(int index)
{
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "frame_%05d.png", index);
    return buffer;
}

void MakeAnimation(const std::string& frameDir, int fps, const std::string& output)
{
    const bool gif = output.size() >= 4 && output.compare(output.size() - 4, 4, ".gif") == 0;
    std::vector<std::string> args = {"ffmpeg",
                                     "-hide_banner",
                                     "-loglevel",
                                     "error",
                                     "-y",
                                     "-framerate",
                                     std::to_string(fps),
                                     "-i",
                                     frameDir + "/frame_%05d.png"};
    if (gif)
    {
        // One palette for the whole animation (ffmpeg's default 256-colour dither otherwise bands badly).
        args.insert(args.end(),
                    {"-vf", "split[a][b];[a]palettegen=stats_mode=diff[p];[b][p]paletteuse=dither=bayer",
                     "-loop", "0"});
    }
    else
    {
        // yuv420p needs even sizes.
        args.insert(args.end(), {"-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-c:v", "libx264", "-pix_fmt",
                                 "yuv420p", "-crf", "23", "-movflags", "+faststart"});
    }
    args.push_back(output);

    std::vector<char*> argv;
    for (std::string& arg : args)
    {
        argv.push_back(arg.data());
    }
    argv.push_back(nullptr);
    pid_t pid = 0;
    const int spawned = posix_spawnp(&pid, "ffmpeg", nullptr, nullptr, argv.data(), environ);
    if (spawned != 0)
    {
        throw std::runtime_error(std::string("cannot start ffmpeg (") + std::strerror(spawned) +
                                 "); install it with scripts/install-deps.sh");
    }
    int status = 0;
    while (waitpid(pid, &status, 0) < 0)
    {
        if (errno != EINTR)
        {
            throw std::runtime_error(std::string("waiting for ffmpeg: ") + std::strerror(errno));
        }
    }
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    {
        throw std::runtime_error("ffmpeg failed making " + output + " (status " + std::to_string(status) +
                                 ")");
    }
}

} // namespace quadphase::scene_cli
