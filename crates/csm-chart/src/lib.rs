//! The SVG helper of csm's charts: `csm report`'s error against run time (the CLI), the
//! benchmark's time against size (`cargo xtask bench`) and the speed-up against threads
//! (`cargo xtask scaling`). It writes the document frame and
//! the elements both draw — lines, polylines, text — with coordinates to one decimal, so that
//! equal charts give equal files, and escapes text for XML. The charts decide their own axes,
//! scales and colours.
//!
//! **Architecture Invariant:** a leaf: no dependency, no knowledge of contact search; only the
//! facade (CLI) and xtask use it.

/// The opening of a `width` × `height` document (sans-serif, 12 px) with a white background;
/// [`close`] ends it.
pub fn open(width: f64, height: f64) -> String {
    format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width}\" height=\"{height}\" \
         viewBox=\"0 0 {width} {height}\" font-family=\"sans-serif\" font-size=\"12\">\n\
         <rect width=\"{width}\" height=\"{height}\" fill=\"white\"/>\n"
    )
}

/// The end of the document.
pub fn close() -> &'static str {
    "</svg>\n"
}

/// `s` with the XML special characters `& < > "` escaped.
pub fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// A line from `(x1, y1)` to `(x2, y2)`; `extra` holds further attributes, each with a
/// leading space (e.g. ` stroke-width="2"`).
pub fn line(x1: f64, y1: f64, x2: f64, y2: f64, stroke: &str, extra: &str) -> String {
    format!(
        "<line x1=\"{x1:.1}\" y1=\"{y1:.1}\" x2=\"{x2:.1}\" y2=\"{y2:.1}\" stroke=\"{stroke}\"{extra}/>"
    )
}

/// Text at `(x, y)`; `attrs` as [`line()`]'s `extra` (e.g. ` text-anchor="middle"`). The text
/// is written as given: escape user text with [`escape`].
pub fn text(x: f64, y: f64, attrs: &str, content: &str) -> String {
    format!("<text x=\"{x:.1}\" y=\"{y:.1}\"{attrs}>{content}</text>")
}

/// The `points` attribute of a polyline: `x,y` pairs separated by spaces.
pub fn points(pts: &[(f64, f64)]) -> String {
    let items: Vec<String> = pts.iter().map(|(x, y)| format!("{x:.1},{y:.1}")).collect();
    items.join(" ")
}

/// An unfilled polyline through `pts` ([`points`]); `extra` as [`line()`]'s.
pub fn polyline(pts: &[(f64, f64)], stroke: &str, extra: &str) -> String {
    format!(
        "<polyline points=\"{}\" fill=\"none\" stroke=\"{stroke}\"{extra}/>",
        points(pts)
    )
}

/// A legend entry at `(x, y)`: a 20-unit sample of the line (`stroke`, `extra` as [`line()`]'s)
/// and the escaped `label` after it, on two lines of the document.
pub fn legend_entry(x: f64, y: f64, stroke: &str, extra: &str, label: &str) -> String {
    format!(
        "{}\n{}",
        line(x, y, x + 20.0, y, stroke, extra),
        text(x + 24.0, y + 4.0, "", &escape(label))
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_legend_entry_is_a_sample_line_and_escaped_text() {
        assert_eq!(
            legend_entry(10.0, 20.0, "red", "", "a < b"),
            "<line x1=\"10.0\" y1=\"20.0\" x2=\"30.0\" y2=\"20.0\" stroke=\"red\"/>\n\
             <text x=\"34.0\" y=\"24.0\">a &lt; b</text>"
        );
    }

    #[test]
    fn elements_have_one_decimal_and_escaped_text() {
        assert_eq!(
            line(1.0, 2.26, 3.0, 4.0, "black", " stroke-width=\"2\""),
            "<line x1=\"1.0\" y1=\"2.3\" x2=\"3.0\" y2=\"4.0\" stroke=\"black\" stroke-width=\"2\"/>"
        );
        assert_eq!(
            text(10.0, 20.0, " text-anchor=\"end\"", &escape("a<b & \"c\"")),
            "<text x=\"10.0\" y=\"20.0\" text-anchor=\"end\">a&lt;b &amp; &quot;c&quot;</text>"
        );
        assert_eq!(
            polyline(&[(0.0, 1.0), (2.54, 3.0)], "red", ""),
            "<polyline points=\"0.0,1.0 2.5,3.0\" fill=\"none\" stroke=\"red\"/>"
        );
        let doc = open(100.0, 50.0) + close();
        assert!(doc.starts_with("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"100\""));
        assert!(doc.contains("<rect width=\"100\" height=\"50\" fill=\"white\"/>"));
        assert!(doc.ends_with("</svg>\n"));
    }
}
