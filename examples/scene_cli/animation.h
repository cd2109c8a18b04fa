// SPDX-License-Identifier: MIT
// GIF and MP4 animations of rendered frames, made by the ffmpeg program.
#pragma once

#include <string>

namespace quadphase::scene_cli
{

/// Name of frame `index` inside the frame directory: frame_00000.png, frame_00001.png, ...
std::string FrameFileName(int index);

/// Runs ffmpeg on DIR/frame_%05d.png (frames 0, 1, 2, ...) at `fps` frames per second and writes `output`:
/// an animated GIF (palette generated from the frames) when it ends in .gif, else an H.264 MP4 (yuv420p, for
/// browsers and players). Blocks until ffmpeg exits. Throws std::runtime_error when ffmpeg cannot be started
/// or fails (its own messages go to stderr).
void MakeAnimation(const std::string& frameDir, int fps, const std::string& output);

} // namespace quadphase::scene_cli
