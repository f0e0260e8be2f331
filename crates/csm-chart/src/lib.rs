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

/// The font size of the charts' text ([`open`]'s), in px.
pub const FONT_SIZE: f64 = 12.0;

/// The font size of a chart's [`title`], in px.
pub const TITLE_SIZE: f64 = 14.0;

/// An upper estimate of the width of `s` drawn at `font_size` px in the viewer's sans-serif
/// font: 0.62 em per character (DejaVu Sans, the widest common default, averages 0.55 em on
/// lowercase text and 0.64 em on digits). Entities (`&amp;`) count as one character.
pub fn text_width(s: &str, font_size: f64) -> f64 {
    let mut chars = 0usize;
    let mut in_entity = false;
    for c in s.chars() {
        match c {
            '&' => {
                in_entity = true;
                chars += 1;
            }
            ';' if in_entity => in_entity = false,
            _ if in_entity => {}
            _ => chars += 1,
        }
    }
    chars as f64 * 0.62 * font_size
}

/// The width a legend of [`legend_entry`]s with `labels` needs right of the plot: a 10-unit
/// gap, the 24-unit sample, the longest label, a 10-unit margin.
pub fn legend_width<'a>(labels: impl IntoIterator<Item = &'a str>) -> f64 {
    let longest = labels
        .into_iter()
        .map(|l| text_width(l, FONT_SIZE))
        .fold(0.0, f64::max);
    10.0 + 24.0 + longest + 10.0
}

/// The chart's title, centred on `x` with its baseline at `y` ([`TITLE_SIZE`]); escaped.
pub fn title(x: f64, y: f64, content: &str) -> String {
    format!(
        "<text x=\"{x:.1}\" y=\"{y:.1}\" text-anchor=\"middle\" font-size=\"{TITLE_SIZE}\" \
         class=\"title\">{}</text>",
        escape(content)
    )
}

/// What keeps the chart `svg` (as this crate writes it) from being complete: no [`title`], or
/// a text that reaches outside the canvas by [`text_width`] (rotated texts by their anchor
/// point). Empty when the chart is fine.
pub fn layout_problems(svg: &str) -> Vec<String> {
    let attr = |tag: &str, key: &str| -> Option<String> {
        let at = tag.find(&format!(" {key}=\""))? + key.len() + 3;
        Some(tag[at..at + tag[at..].find('"')?].to_owned())
    };
    let number = |tag: &str, key: &str| attr(tag, key).and_then(|v| v.parse::<f64>().ok());
    let mut problems = Vec::new();
    let Some(head) = svg.split('>').next() else {
        return vec!["no <svg> element".to_owned()];
    };
    let (Some(width), Some(height)) = (number(head, "width"), number(head, "height")) else {
        return vec!["the <svg> element has no width or height".to_owned()];
    };
    if !svg.contains("class=\"title\"") {
        problems.push("no title".to_owned());
    }
    for piece in svg.split("<text").skip(1) {
        let Some(close) = piece.find('>') else {
            continue;
        };
        let tag = &piece[..close];
        let content = &piece[close + 1..piece.find("</text>").unwrap_or(close + 1)];
        let (x, y) = (
            number(tag, "x").unwrap_or(0.0),
            number(tag, "y").unwrap_or(0.0),
        );
        let size = number(tag, "font-size").unwrap_or(FONT_SIZE);
        let w = if tag.contains("transform=") {
            0.0
        } else {
            text_width(content, size)
        };
        let (x0, x1) = match attr(tag, "text-anchor").as_deref() {
            Some("middle") => (x - w / 2.0, x + w / 2.0),
            Some("end") => (x - w, x),
            _ => (x, x + w),
        };
        if x0 < 0.0 || x1 > width || y - size < -1.0 || y > height {
            problems.push(format!(
                "text `{content}` spans x {x0:.0}..{x1:.0}, y {:.0}..{y:.0}: outside the \
                 {width} × {height} canvas",
                y - size
            ));
        }
    }
    problems
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
    fn layout_problems_finds_a_cut_legend_and_a_missing_title() {
        let label = "stacked_blocks csm 2 threads";
        let mut svg = open(300.0, 100.0);
        svg.push_str(&legend_entry(200.0, 50.0, "red", "", label));
        svg.push_str(close());
        let problems = layout_problems(&svg);
        assert_eq!(problems.len(), 2, "{problems:?}");
        assert_eq!(problems[0], "no title");
        assert!(problems[1].starts_with("text `stacked_blocks csm 2 threads` spans x 224..432"));
        // Room for the legend and a title: nothing to report.
        let w = 200.0 + legend_width([label]);
        let mut svg = open(w, 100.0);
        svg.push_str(&title(w / 2.0, 20.0, "a & b"));
        svg.push_str(&legend_entry(200.0 + 10.0, 50.0, "red", "", label));
        svg.push_str(close());
        assert_eq!(layout_problems(&svg), Vec::<String>::new());
        assert_eq!(text_width("a &amp; b", 10.0), 5.0 * 6.2);
    }

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
