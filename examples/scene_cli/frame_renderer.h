// SPDX-License-Identifier: MIT
// Draws a world (and its quadtree overlay) into a PNG with cairo.
#pragma once

#include <string>
#include <vector>

#include "box2d/box2d.h"
#include "quadtree_overlay.h"
#include "scene_cli_options.h"

namespace quadphase::scene_cli
{

struct FrameText
{
    std::vector<std::string> lines; ///< drawn top-left, one per line
};

/// Renders frames of one size and one world rectangle. The rectangle is fitted into the image keeping its
/// aspect ratio (uniform scale, centred). Not thread-safe; one renderer per thread.
class FrameRenderer
{
public:
    FrameRenderer(int width, int height, const ViewRect& view);

    /// Draws the overlay cells (when overlay.available and drawOverlay), then every fixture, then the text,
    /// the legend and a scale bar, and writes a PNG to `path`. Throws std::runtime_error when cairo cannot
    /// write it.
    void Render(const b2World& world, const Overlay& overlay, bool drawOverlay, const FrameText& text,
                const std::string& path) const;

private:
    int m_width;
    int m_height;
    ViewRect m_view;
    double m_scale;   // pixels per metre
    double m_offsetX; // pixel x of world x = 0
    double m_offsetY; // pixel y of world y = 0 (y grows downwards in the image)
};

} // namespace quadphase::scene_cli
