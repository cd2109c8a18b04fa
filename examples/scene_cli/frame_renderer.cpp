// SPDX-License-Identifier: MIT
// Cairo drawing of bodies, quadtree cells, text, legend and scale bar.
#include "frame_renderer.h"

#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>

namespace quadphase::scene_cli
{

namespace
{

struct Rgb
{
    double r, g, b;
};

/// Level colours: distinct hues, cycled for pyramids deeper than the table.
constexpr Rgb kLevelColours[] = {
    {0.90, 0.30, 0.30}, {0.95, 0.60, 0.20}, {0.90, 0.85, 0.25}, {0.45, 0.80, 0.30},
    {0.25, 0.75, 0.70}, {0.30, 0.55, 0.95}, {0.60, 0.40, 0.95}, {0.90, 0.40, 0.80},
};

const Rgb& LevelColour(int level)
{
    return kLevelColours[size_t(level) % (sizeof kLevelColours / sizeof kLevelColours[0])];
}

using Surface = std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)>;
using Context = std::unique_ptr<cairo_t, decltype(&cairo_destroy)>;

/// 1 2 5 10 20 50 ... closest below `value`.
double NiceBelow(double value)
{
    const double power = std::pow(10.0, std::floor(std::log10(value)));
    for (double step : {5.0, 2.0, 1.0})
    {
        if (step * power <= value)
        {
            return step * power;
        }
    }
    return power;
}

} // namespace

FrameRenderer::FrameRenderer(int width, int height, const ViewRect& view)
    : m_width(width), m_height(height), m_view(view)
{
    const double viewWidth = double(view.maxX) - double(view.minX);
    const double viewHeight = double(view.maxY) - double(view.minY);
    m_scale = std::min(double(width) / viewWidth, double(height) / viewHeight);
    const double centreX = 0.5 * (double(view.minX) + double(view.maxX));
    const double centreY = 0.5 * (double(view.minY) + double(view.maxY));
    m_offsetX = 0.5 * width - m_scale * centreX;
    m_offsetY = 0.5 * height + m_scale * centreY;
}

void FrameRenderer::Render(const b2World& world, const Overlay& overlay, bool drawOverlay,
                           const FrameText& text, const std::string& path) const
{
    Surface surface(cairo_image_surface_create(CAIRO_FORMAT_RGB24, m_width, m_height),
                    &cairo_surface_destroy);
    Context cr(cairo_create(surface.get()), &cairo_destroy);
    cairo_t* c = cr.get();
    // World coordinates are converted by hand (double precision: a map 50 km from the origin keeps its
    // millimetres), so line widths stay in pixels.
    auto px = [this](double x) {
        return m_offsetX + m_scale * x;
    };
    auto py = [this](double y) {
        return m_offsetY - m_scale * y;
    };
    const double viewMinX = (0.0 - m_offsetX) / m_scale;
    const double viewMaxX = (double(m_width) - m_offsetX) / m_scale;
    const double viewMaxY = (m_offsetY - 0.0) / m_scale;
    const double viewMinY = (m_offsetY - double(m_height)) / m_scale;

    cairo_set_source_rgb(c, 0.06, 0.07, 0.09);
    cairo_paint(c);

    // Quadtree cells: filled by occupancy (sqrt, so sparse cells stay visible), outlined in the level colour.
    if (overlay.available && drawOverlay)
    {
        const double largest = std::max(1, overlay.largestCount);
        cairo_set_line_width(c, 1.0);
        for (const OverlayCell& cell : overlay.cells)
        {
            if (cell.x > viewMaxX || cell.y > viewMaxY || cell.x + cell.side < viewMinX ||
                cell.y + cell.side < viewMinY)
            {
                continue;
            }
            const Rgb& colour = LevelColour(cell.level);
            const double x0 = px(cell.x);
            const double y0 = py(double(cell.y) + double(cell.side));
            const double s = std::max(1.0, m_scale * cell.side);
            const double fill = 0.10 + 0.45 * std::sqrt(double(cell.count) / largest);
            cairo_rectangle(c, x0, y0, s, s);
            cairo_set_source_rgba(c, colour.r, colour.g, colour.b, fill);
            cairo_fill_preserve(c);
            cairo_set_source_rgba(c, colour.r, colour.g, colour.b, 0.75);
            cairo_stroke(c);
        }
    }

    // Bodies.
    cairo_set_line_width(c, 1.0);
    cairo_set_line_join(c, CAIRO_LINE_JOIN_ROUND);
    for (const b2Body* body = world.GetBodyList(); body != nullptr; body = body->GetNext())
    {
        Rgb colour{0.75, 0.75, 0.75};
        if (body->GetType() == b2_kinematicBody)
        {
            colour = Rgb{0.45, 0.75, 1.0};
        }
        else if (body->GetType() == b2_dynamicBody)
        {
            colour = body->IsAwake() ? Rgb{1.0, 1.0, 1.0} : Rgb{0.55, 0.55, 0.62};
        }
        const b2Transform& xf = body->GetTransform();
        // A new path through the vertices, in body coordinates (open: the caller closes it if it must).
        auto polyline = [&](const b2Vec2* vertices, int32 count) {
            cairo_new_path(c);
            for (int32 i = 0; i < count; ++i)
            {
                const b2Vec2 p = b2Mul(xf, vertices[i]);
                if (i == 0)
                {
                    cairo_move_to(c, px(p.x), py(p.y));
                }
                else
                {
                    cairo_line_to(c, px(p.x), py(p.y));
                }
            }
        };
        for (const b2Fixture* fixture = body->GetFixtureList(); fixture != nullptr;
             fixture = fixture->GetNext())
        {
            const b2Shape* shape = fixture->GetShape();
            if (shape->GetType() != b2Shape::e_chain)
            {
                b2AABB aabb;
                shape->ComputeAABB(&aabb, xf, 0);
                if (aabb.lowerBound.x > viewMaxX || aabb.lowerBound.y > viewMaxY ||
                    aabb.upperBound.x < viewMinX || aabb.upperBound.y < viewMinY)
                {
                    continue;
                }
            }
            bool closed = true;
            switch (shape->GetType())
            {
            case b2Shape::e_circle:
            {
                const auto* circle = static_cast<const b2CircleShape*>(shape);
                const b2Vec2 centre = b2Mul(xf, circle->m_p);
                const double r = std::max(0.6, m_scale * circle->m_radius);
                cairo_new_path(c);
                cairo_arc(c, px(centre.x), py(centre.y), r, 0.0, 2.0 * double(b2_pi));
                if (r > 3.0)
                {
                    // A radius line shows the rotation.
                    const b2Vec2 edge = centre + circle->m_radius * xf.q.GetXAxis();
                    cairo_move_to(c, px(centre.x), py(centre.y));
                    cairo_line_to(c, px(edge.x), py(edge.y));
                }
                break;
            }
            case b2Shape::e_polygon:
            {
                const auto* polygon = static_cast<const b2PolygonShape*>(shape);
                polyline(polygon->m_vertices, polygon->m_count);
                cairo_close_path(c);
                break;
            }
            case b2Shape::e_edge:
            {
                const auto* edge = static_cast<const b2EdgeShape*>(shape);
                const b2Vec2 a = b2Mul(xf, edge->m_vertex1);
                const b2Vec2 b = b2Mul(xf, edge->m_vertex2);
                cairo_new_path(c);
                cairo_move_to(c, px(a.x), py(a.y));
                cairo_line_to(c, px(b.x), py(b.y));
                closed = false;
                break;
            }
            case b2Shape::e_chain:
            {
                const auto* chain = static_cast<const b2ChainShape*>(shape);
                polyline(chain->m_vertices, chain->m_count);
                closed = false;
                break;
            }
            default:
                continue;
            }
            if (closed)
            {
                cairo_set_source_rgba(c, colour.r, colour.g, colour.b, 0.25);
                cairo_fill_preserve(c);
            }
            cairo_set_source_rgba(c, colour.r, colour.g, colour.b, 0.95);
            cairo_set_line_width(c, closed ? 1.0 : 2.0);
            cairo_stroke(c);
        }
    }

    // Text, top left, on a dark band.
    cairo_select_font_face(c, "DejaVu Sans Mono", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    const double fontSize = std::clamp(double(m_height) / 45.0, 9.0, 16.0);
    cairo_set_font_size(c, fontSize);
    const double lineHeight = 1.3 * fontSize;
    if (!text.lines.empty())
    {
        double widest = 0.0;
        for (const std::string& line : text.lines)
        {
            cairo_text_extents_t extents;
            cairo_text_extents(c, line.c_str(), &extents);
            widest = std::max(widest, extents.x_advance);
        }
        cairo_rectangle(c, 0.0, 0.0, widest + 12.0, lineHeight * double(text.lines.size()) + 8.0);
        cairo_set_source_rgba(c, 0.0, 0.0, 0.0, 0.65);
        cairo_fill(c);
        cairo_set_source_rgb(c, 0.95, 0.95, 0.95);
        for (size_t i = 0; i < text.lines.size(); ++i)
        {
            cairo_move_to(c, 6.0, 4.0 + lineHeight * (double(i) + 0.8));
            cairo_show_text(c, text.lines[i].c_str());
        }
    }

    // Legend, top right: the levels in use.
    if (overlay.available && drawOverlay)
    {
        std::vector<std::string> rows;
        std::vector<int> levels;
        for (size_t level = 0; level < overlay.cellsPerLevel.size(); ++level)
        {
            if (overlay.cellsPerLevel[level] > 0)
            {
                char buffer[96];
                std::snprintf(buffer, sizeof buffer, "L%-2zu %6d cells %7d proxies", level,
                              overlay.cellsPerLevel[level], overlay.proxiesPerLevel[level]);
                rows.emplace_back(buffer);
                levels.push_back(int(level));
            }
        }
        double widest = 0.0;
        for (const std::string& row : rows)
        {
            cairo_text_extents_t extents;
            cairo_text_extents(c, row.c_str(), &extents);
            widest = std::max(widest, extents.x_advance);
        }
        const double boxWidth = widest + lineHeight + 16.0;
        const double x0 = double(m_width) - boxWidth;
        cairo_rectangle(c, x0, 0.0, boxWidth, lineHeight * double(rows.size()) + 8.0);
        cairo_set_source_rgba(c, 0.0, 0.0, 0.0, 0.65);
        cairo_fill(c);
        for (size_t i = 0; i < rows.size(); ++i)
        {
            const Rgb& colour = LevelColour(levels[i]);
            const double top = 4.0 + lineHeight * double(i);
            cairo_rectangle(c, x0 + 6.0, top + 0.15 * lineHeight, 0.7 * lineHeight, 0.7 * lineHeight);
            cairo_set_source_rgba(c, colour.r, colour.g, colour.b, 0.8);
            cairo_fill(c);
            cairo_set_source_rgb(c, 0.95, 0.95, 0.95);
            cairo_move_to(c, x0 + 10.0 + lineHeight, top + 0.8 * lineHeight);
            cairo_show_text(c, rows[i].c_str());
        }
    }

    // Scale bar, bottom left.
    {
        const double metres = NiceBelow(0.2 * double(m_width) / m_scale);
        const double length = metres * m_scale;
        const double y = double(m_height) - 10.0;
        cairo_set_source_rgb(c, 0.95, 0.95, 0.95);
        cairo_set_line_width(c, 2.0);
        cairo_move_to(c, 10.0, y);
        cairo_line_to(c, 10.0 + length, y);
        cairo_stroke(c);
        char label[48];
        std::snprintf(label, sizeof label, metres >= 1.0 ? "%.0f m" : "%.2g m", metres);
        cairo_move_to(c, 14.0 + length, y + 0.35 * fontSize);
        cairo_show_text(c, label);
    }

    cairo_surface_flush(surface.get());
    const cairo_status_t status = cairo_surface_write_to_png(surface.get(), path.c_str());
    if (status != CAIRO_STATUS_SUCCESS)
    {
        throw std::runtime_error("cannot write " + path + ": " + cairo_status_to_string(status));
    }
}

} // namespace quadphase::scene_cli
