//! The house style: drawing at three times the shown size so lines and
//! dots sit at sub-pixel positions (the SVG backend writes whole numbers).

use std::path::Path;

use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

/// Drawn at `SCALE` × the shown size; the SVG's `width`/`height` say the
/// shown size and its `viewBox` the drawn one.
pub const SCALE: u32 = 3;

/// Line colours (colour-blind-safe first four).
pub const COLORS: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(255, 127, 14),
    RGBColor(0, 0, 0),
];

/// Dash patterns (dash, gap) in shown pixels; index 0 is unused (solid).
pub const DASHES: [(u32, u32); 4] = [(0, 0), (7, 4), (2, 3), (12, 4)];

/// A length in shown pixels, in drawn ones.
pub fn px(n: u32) -> u32 {
    n * SCALE
}

/// A font of `size` shown points.
pub fn font(size: u32) -> (&'static str, u32) {
    ("sans-serif", px(size))
}

/// A line style of `width` shown pixels.
pub fn line(color: RGBColor, width: u32) -> ShapeStyle {
    ShapeStyle::from(color).stroke_width(px(width))
}

/// A chart over f64 ranges on an SVG figure.
pub type Chart<'a, 'b> =
    ChartContext<'a, SVGBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// Draws the grid, ticks and axis titles in the house style: light major
/// grid lines only, labels at the shown sizes, `fx`/`fy` formatting the
/// ticks ([`tick`], [`decade`], or a caller's).
pub fn axes(
    c: &mut Chart<'_, '_>,
    x: &str,
    y: &str,
    fx: &dyn Fn(&f64) -> String,
    fy: &dyn Fn(&f64) -> String,
    label_size: u32,
) -> Result<(), String> {
    c.configure_mesh()
        .x_desc(x)
        .y_desc(y)
        .x_label_formatter(fx)
        .y_label_formatter(fy)
        .label_style(font(label_size))
        .axis_desc_style(font(label_size + 2))
        .light_line_style(WHITE.mix(0.0))
        .bold_line_style(BLACK.mix(0.1))
        .draw()
        .map_err(|e| e.to_string())
}

/// One legend row: a short line (dashed when the series is) and a label.
pub struct Entry {
    /// What the series is.
    pub label: String,
    /// Its colour.
    pub color: RGBColor,
    /// Dash pattern: 0 solid, else one of [`DASHES`] (desired values; the
    /// three components get three patterns, so that curves lying on one
    /// another stay apart).
    pub dash: usize,
    /// Drawn with dots at its points.
    pub dots: bool,
    /// Drawn as a line (false: dots only, a scatter).
    pub line: bool,
}

/// A region of an SVG figure.
pub type Area<'a> = DrawingArea<SVGBackend<'a>, Shift>;

/// The drawing area for a figure of `shown` pixels, white, split into the
/// plot (left) and a legend panel `legend_width` shown pixels wide (right;
/// 0 for none).
pub fn canvas(
    path: &Path,
    shown: (u32, u32),
    legend_width: u32,
) -> Result<(Area<'_>, Area<'_>), String> {
    let root = SVGBackend::new(path, (px(shown.0), px(shown.1))).into_drawing_area();
    root.fill(&WHITE)
        .map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(root.split_horizontally(px(shown.0 - legend_width)))
}

/// Draws `entries` top-down in `area`, starting `top` shown pixels down
/// (level with the plot's top edge).
pub fn legend(area: &Area<'_>, entries: &[Entry], top: u32) -> Result<(), String> {
    let e = |x: &dyn std::fmt::Display| x.to_string();
    let row = px(19) as i32;
    for (k, en) in entries.iter().enumerate() {
        let y = px(top) as i32 + k as i32 * row;
        let (x0, x1) = (px(6) as i32, px(34) as i32);
        let style = line(en.color, 2);
        if !en.line {
        } else if en.dash > 0 {
            let (d, g) = DASHES[en.dash % DASHES.len()];
            let (d, g) = (px(d) as i32, px(g) as i32);
            let mut x = x0;
            while x < x1 {
                area.draw(&PathElement::new(vec![(x, y), ((x + d).min(x1), y)], style))
                    .map_err(|x| e(&x))?;
                x += d + g;
            }
        } else {
            area.draw(&PathElement::new(vec![(x0, y), (x1, y)], style))
                .map_err(|x| e(&x))?;
        }
        if en.dots {
            area.draw(&Circle::new(((x0 + x1) / 2, y), px(2), en.color.filled()))
                .map_err(|x| e(&x))?;
        }
        area.draw(&Text::new(
            en.label.clone(),
            (px(40) as i32, y - px(7) as i32),
            font(13),
        ))
        .map_err(|x| e(&x))?;
    }
    Ok(())
}

/// Writes the figure and gives it its shown size.
pub fn finish(root: Area<'_>, path: &Path, shown: (u32, u32)) -> Result<(), String> {
    let err = |e: &dyn std::fmt::Display| format!("{}: {e}", path.display());
    root.present().map_err(|e| err(&e))?;
    drop(root);
    let text = std::fs::read_to_string(path).map_err(|e| err(&e))?;
    let drawn = format!("width=\"{}\" height=\"{}\"", px(shown.0), px(shown.1));
    let text = text.replacen(
        &drawn,
        &format!("width=\"{}\" height=\"{}\"", shown.0, shown.1),
        1,
    );
    std::fs::write(path, text).map_err(|e| err(&e))
}

/// A tick label: as few decimals as the value needs (up to 4), no `-0`.
pub fn tick(v: &f64) -> String {
    let mut s = format!("{v:.4}");
    if s.contains('.') {
        s = s.trim_end_matches('0').trim_end_matches('.').to_string();
    }
    if s == "-0" { "0".into() } else { s }
}

/// A tick label for a power of ten given by its exponent (`-6` → `1e-6`).
pub fn decade(v: &f64) -> String {
    let r = v.round();
    if (v - r).abs() < 1e-9 {
        format!("1e{}", r as i64)
    } else {
        String::new()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_read_plainly() {
        assert_eq!(tick(&-0.0), "0");
        assert_eq!(tick(&-0.00001), "0");
        assert_eq!(tick(&2.0), "2");
        assert_eq!(tick(&180.0), "180");
        assert_eq!(tick(&0.25), "0.25");
        assert_eq!(tick(&-1.5), "-1.5");
        assert_eq!(decade(&-6.0), "1e-6");
        assert_eq!(decade(&-6.5), "");
    }
}
