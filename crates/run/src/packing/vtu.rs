//! Reading a packing from a VTK XML file (`.vtu`), as far as hopperflow writes one
//! (`output::vtu`): one piece, its points, a point-data array `radius` and, for a mixture, one
//! named `component` (each particle's component, an index), stored inline
//! as ASCII. That is read without an XML library: the elements needed are found by their
//! tags, and their attributes and text read directly. Binary (base64), appended or
//! compressed data are refused with a message that says how to save the file as ASCII.

use super::read::{PackingPlace, Problems, RawParticle};

/// An element's start tag: its attributes, and the text up to its end tag.
struct Element<'a> {
    attributes: Vec<(&'a str, &'a str)>,
    /// The content between the start and end tags (empty for `<X/>`).
    content: &'a str,
}

impl Element<'_> {
    fn attribute(&self, name: &str) -> Option<&str> {
        self.attributes
            .iter()
            .find(|(key, _)| *key == name)
            .map(|(_, value)| *value)
    }
}

/// The attributes `key="value"` (or single quotes) of a start tag's inside.
fn attributes(tag: &str) -> Vec<(&str, &str)> {
    let mut out = Vec::new();
    let mut rest = tag;
    while let Some(eq) = rest.find('=') {
        let key = rest[..eq].split_whitespace().last().unwrap_or("");
        let after = rest[eq + 1..].trim_start();
        let Some(quote) = after.chars().next().filter(|c| *c == '"' || *c == '\'') else {
            break;
        };
        let Some(end) = after[1..].find(quote) else {
            break;
        };
        out.push((key, &after[1..1 + end]));
        rest = &after[end + 2..];
    }
    out
}

/// Every element named `name` in `text`, in order, with its content (elements of the same
/// name are not nested in a VTU file).
fn elements<'a>(text: &'a str, name: &str) -> Vec<Element<'a>> {
    let open = format!("<{name}");
    let close = format!("</{name}>");
    let mut out = Vec::new();
    let mut rest = text;
    while let Some(start) = rest.find(&open) {
        let after = &rest[start + open.len()..];
        // `<Points>` but not `<PointsX`: the name must end there.
        if !after.starts_with(|c: char| c.is_whitespace() || c == '>' || c == '/') {
            rest = after;
            continue;
        }
        let Some(end) = after.find('>') else {
            break;
        };
        let tag = &after[..end];
        if let Some(inside) = tag.strip_suffix('/') {
            out.push(Element {
                attributes: attributes(inside),
                content: "",
            });
            rest = &after[end + 1..];
            continue;
        }
        let body = &after[end + 1..];
        let stop = body.find(&close).unwrap_or(body.len());
        out.push(Element {
            attributes: attributes(tag),
            content: &body[..stop],
        });
        rest = &body[stop..];
    }
    out
}

/// The values of an inline ASCII data array, `components` per point, `points` points.
fn ascii_values(
    array: &Element<'_>,
    name: &str,
    components: usize,
    points: usize,
    problems: &mut Problems,
) -> Option<Vec<f64>> {
    let place = |index| PackingPlace::Array {
        name: name.to_string(),
        index,
    };
    let format = array.attribute("format").unwrap_or("ascii");
    if format != "ascii" {
        problems.push(
            PackingPlace::File,
            format!(
                "array `{name}` is stored as `{format}`; hopperflow reads VTU data stored inline \
                 as ASCII (what its own snapshots hold): save the file from ParaView with Data \
                 Mode `Ascii`"
            ),
        );
        return None;
    }
    let declared = array
        .attribute("NumberOfComponents")
        .map_or(Ok(1), str::parse::<usize>);
    if declared != Ok(components) {
        problems.push(
            PackingPlace::File,
            format!(
                "array `{name}` has NumberOfComponents = {}; {components} are needed",
                array.attribute("NumberOfComponents").unwrap_or("1")
            ),
        );
        return None;
    }
    // Not sized by the declared count: a damaged NumberOfPoints must not allocate.
    let mut values = Vec::new();
    let mut good = true;
    for (index, token) in array.content.split_whitespace().enumerate() {
        match token.parse::<f64>() {
            Ok(v) => values.push(v),
            Err(_) => {
                problems.push(place(index), format!("`{token}` is not a number"));
                good = false;
            }
        }
    }
    if !good {
        return None;
    }
    if Some(values.len()) != points.checked_mul(components) {
        problems.push(
            PackingPlace::File,
            format!(
                "array `{name}` holds {} values; NumberOfPoints = {points} needs \
                 {components} per point",
                values.len(),
            ),
        );
        return None;
    }
    Some(values)
}

/// The particles of a VTU file's `text`, or `None` with the problems pushed.
pub(super) fn parse_vtu(text: &str, problems: &mut Problems) -> Option<Vec<RawParticle>> {
    let Some(file) = elements(text, "VTKFile").into_iter().next() else {
        problems.push(
            PackingPlace::File,
            "is not a VTK XML file: it has no <VTKFile> element",
        );
        return None;
    };
    let kind = file.attribute("type").unwrap_or("");
    if kind != "UnstructuredGrid" && kind != "PolyData" {
        problems.push(
            PackingPlace::File,
            format!(
                "is a VTK `{kind}` file; a packing is an UnstructuredGrid (or PolyData) of points"
            ),
        );
        return None;
    }
    if let Some(compressor) = file.attribute("compressor") {
        problems.push(
            PackingPlace::File,
            format!(
                "is compressed ({compressor}); hopperflow reads uncompressed VTU data stored \
                 inline as ASCII: save the file from ParaView with Data Mode `Ascii`"
            ),
        );
        return None;
    }
    let pieces = elements(text, "Piece");
    let [piece] = &pieces[..] else {
        problems.push(
            PackingPlace::File,
            format!(
                "has {} pieces; a packing is read from a file of one piece",
                pieces.len()
            ),
        );
        return None;
    };
    let points = match piece.attribute("NumberOfPoints").map(str::parse::<usize>) {
        Some(Ok(n)) => n,
        other => {
            problems.push(
                PackingPlace::File,
                format!(
                    "its piece has no readable NumberOfPoints ({})",
                    match other {
                        None => "absent".to_string(),
                        Some(_) => format!(
                            "`{}`",
                            piece.attribute("NumberOfPoints").unwrap_or_default()
                        ),
                    }
                ),
            );
            return None;
        }
    };
    if points == 0 {
        problems.push(
            PackingPlace::File,
            "has no points: a packing needs one point per particle",
        );
        return None;
    }
    let position_array = elements(piece.content, "Points")
        .into_iter()
        .next()
        .and_then(|section| {
            elements(section.content, "DataArray")
                .into_iter()
                .next()
                .map(|array| {
                    (
                        array.attribute("Name").unwrap_or("Points").to_string(),
                        array,
                    )
                })
        });
    let Some((position_name, position_array)) = position_array else {
        problems.push(
            PackingPlace::File,
            "has no <Points> data array: a packing needs the particles' centres",
        );
        return None;
    };
    let point_data: Vec<Element<'_>> = elements(piece.content, "PointData")
        .into_iter()
        .flat_map(|section| elements(section.content, "DataArray"))
        .collect();
    let Some(radius_array) = point_data
        .iter()
        .find(|a| a.attribute("Name") == Some("radius"))
    else {
        let names: Vec<&str> = point_data
            .iter()
            .filter_map(|a| a.attribute("Name"))
            .collect();
        problems.push(
            PackingPlace::File,
            format!(
                "has no point-data array named `radius` (its point data: {}); a packing needs \
                 each particle's radius [m]",
                if names.is_empty() {
                    "none".to_string()
                } else {
                    names.join(", ")
                }
            ),
        );
        return None;
    };
    let positions = ascii_values(&position_array, &position_name, 3, points, problems);
    let radii = ascii_values(radius_array, "radius", 1, points, problems);
    // A mixture's snapshot gives each particle's component (an index into
    // particles.components); the checks against the case read it.
    let components = point_data
        .iter()
        .find(|a| a.attribute("Name") == Some("component"))
        .map(|array| ascii_values(array, "component", 1, points, problems));
    let (positions, radii) = (positions?, radii?);
    let components = match components {
        Some(values) => Some(values?),
        None => None,
    };
    Some(
        (0..points)
            .map(|k| RawParticle {
                place: PackingPlace::Point(k),
                position: [positions[3 * k], positions[3 * k + 1], positions[3 * k + 2]],
                radius: radii[k],
                label: None,
                component: components.as_ref().map(|c| c[k]),
            })
            .collect(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn attributes_and_elements_are_read_as_written() {
        let a = attributes(r#" type="Float64" Name='radius' format="ascii""#);
        assert_eq!(
            a,
            vec![("type", "Float64"), ("Name", "radius"), ("format", "ascii")]
        );
        let text = "<Points><DataArray Name=\"p\">1 2 3</DataArray></Points><PointData/>";
        let points = elements(text, "Points");
        assert_eq!(points.len(), 1);
        let arrays = elements(points[0].content, "DataArray");
        assert_eq!(arrays[0].content, "1 2 3");
        assert_eq!(elements(text, "PointData")[0].content, "");
        // `<Point` must not match `<PointData` or `<Points`.
        assert!(elements(text, "Point").is_empty());
    }
}
