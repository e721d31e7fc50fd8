//! Reader of Stanford PLY models, ASCII or binary (either byte order).
//!
//! The `vertex` element needs scalar properties `x`, `y` and `z` (any numeric type);
//! the `face` element needs an integer list property `vertex_indices` (or
//! `vertex_index`). Other properties and elements are read past and ignored. Vertices
//! keep the file's numbering (from 0), faces the file's winding.
//!
//! The header is parsed by `ply-rs-bw` after a scan of its own that gives line numbers
//! to the common header mistakes; binary payloads are decoded by `ply-rs-bw`, one
//! element at a time so that errors name the byte; ASCII payloads are parsed here so
//! that errors name the line and the offending value.

use std::io::{Cursor, ErrorKind, Read};

use ply_rs_bw::parser::{Parser, Reader};
use ply_rs_bw::ply::{
    ElementDef, Encoding, Header, Property, PropertyAccess, PropertyAccessResult, PropertyType, ScalarType,
};

use super::text::{TextLines, finite_vertex, parse_f64, read_limited, to_u32};
use super::{MeshSoup, ParseError, Place};

/// Reads a PLY model, ASCII or binary.
///
/// # Errors
/// A [`ParseError`]: a malformed header, a missing `vertex` or `face` element, missing
/// `x`/`y`/`z` properties or face index list (at the header line concerned); a
/// non-numeric or non-finite value, a wrong number of values, a face with fewer than 3
/// vertices or a negative or out-of-range index, fewer elements than declared or data
/// after the last one (at the payload line for ASCII, the byte for binary).
pub fn read(reader: impl Read) -> Result<MeshSoup, ParseError> {
    let bytes = read_limited(reader)?;
    let scan = scan_header(&bytes)?;
    let parser = Parser::<Record>::new();
    let mut header_reader = Reader::new(Cursor::new(bytes.as_slice()));
    let header = parser.read_header(&mut header_reader).map_err(|e| {
        let place = e.line().map_or(Place::Whole, Place::Line);
        ParseError::new(
            place,
            format!("invalid PLY header: {}", ply_message(&e)),
            "each header line is `format ...`, `element <name> <count>`, `property <type> <name>`, `property list <count type> <item type> <name>`, `comment ...` or `end_header`",
        )
    })?;
    let data_start = header_reader.get_ref().position();
    let layout = Layout::check(&header, &scan)?;
    let mut soup = Soup::default();
    let payload = usize::try_from(data_start)
        .ok()
        .and_then(|start| bytes.get(start..))
        .unwrap_or_default();
    match header.encoding {
        Encoding::Ascii => read_ascii(payload, &header, &scan, &layout, &mut soup)?,
        Encoding::BinaryLittleEndian | Encoding::BinaryBigEndian => {
            read_binary(&parser, &bytes, data_start, &header, &mut soup)?;
        }
    }
    soup.finish()
}

/// One element record as `ply-rs-bw` decodes it: only the properties this reader uses.
#[derive(Debug, Default)]
struct Record {
    xyz: [f64; 3],
    indices: Vec<i64>,
}

impl PropertyAccess for Record {
    fn new() -> Self {
        Self::default()
    }

    fn set_property(&mut self, name: &str, property: Property) -> PropertyAccessResult {
        let axis = match name {
            "x" => 0,
            "y" => 1,
            "z" => 2,
            "vertex_indices" | "vertex_index" => {
                self.indices = match property {
                    Property::ListChar(v) => v.into_iter().map(i64::from).collect(),
                    Property::ListUChar(v) => v.into_iter().map(i64::from).collect(),
                    Property::ListShort(v) => v.into_iter().map(i64::from).collect(),
                    Property::ListUShort(v) => v.into_iter().map(i64::from).collect(),
                    Property::ListInt(v) => v.into_iter().map(i64::from).collect(),
                    Property::ListUInt(v) => v.into_iter().map(i64::from).collect(),
                    _ => return PropertyAccessResult::Ignored,
                };
                return PropertyAccessResult::Set;
            }
            _ => return PropertyAccessResult::Ignored,
        };
        let value = match property {
            Property::Char(v) => f64::from(v),
            Property::UChar(v) => f64::from(v),
            Property::Short(v) => f64::from(v),
            Property::UShort(v) => f64::from(v),
            Property::Int(v) => f64::from(v),
            Property::UInt(v) => f64::from(v),
            Property::Float(v) => f64::from(v),
            Property::Double(v) => v,
            _ => return PropertyAccessResult::Ignored,
        };
        if let Some(slot) = self.xyz.get_mut(axis) {
            *slot = value;
        }
        PropertyAccessResult::Set
    }
}

/// The soup being built; faces wait for the vertex count (the `face` element may come
/// before the `vertex` element).
#[derive(Default)]
struct Soup {
    positions: Vec<glam::DVec3>,
    faces: Vec<(Place, Vec<u64>)>,
}

impl Soup {
    fn take(&mut self, element: &str, index: usize, record: Record, place: Place) -> Result<(), ParseError> {
        match element {
            "vertex" => {
                self.positions
                    .push(finite_vertex(record.xyz, &format!("vertex {index}"), place)?);
            }
            "face" => {
                let corners = record.indices.len();
                if corners < 3 {
                    return Err(ParseError::new(
                        place,
                        format!("face {index} has {corners} vertices; a face needs at least 3"),
                        "remove the degenerate face or re-export the model",
                    ));
                }
                let mut polygon = Vec::with_capacity(corners);
                for vertex in record.indices {
                    let Ok(vertex) = u64::try_from(vertex) else {
                        return Err(ParseError::new(
                            place,
                            format!("face {index} refers to vertex {vertex}; PLY indices cannot be negative"),
                            "vertex indices of a PLY file count from 0",
                        ));
                    };
                    polygon.push(vertex);
                }
                self.faces.push((place, polygon));
            }
            _ => {}
        }
        Ok(())
    }

    fn finish(self) -> Result<MeshSoup, ParseError> {
        let vertex_count = self.positions.len();
        let mut soup = MeshSoup {
            positions: self.positions,
            polygon_noun: "face",
            ..MeshSoup::default()
        };
        soup.polygons.reserve(self.faces.len());
        soup.polygon_lines.reserve(self.faces.len());
        for (face, (place, corners)) in self.faces.into_iter().enumerate() {
            let mut polygon = Vec::with_capacity(corners.len());
            for vertex in corners {
                let index = usize::try_from(vertex).ok().filter(|&v| v < vertex_count).ok_or_else(|| {
                    ParseError::new(
                        place,
                        format!("face {face} refers to vertex {vertex} but the file has {vertex_count} vertices"),
                        "vertex indices of a PLY file count from 0; check the face and the vertex count in the header",
                    )
                })?;
                polygon.push(to_u32(index, place)?);
            }
            soup.polygons.push(polygon);
            soup.polygon_lines.push(match place {
                Place::Line(line) => Some(line),
                Place::Byte(_) | Place::Whole => None,
            });
        }
        Ok(soup)
    }
}

/// Where the header declares each element and property.
struct HeaderScan {
    /// The line of `end_header`.
    end_line: usize,
    /// The elements, in header order.
    elements: Vec<ElementScan>,
}

/// Where the header declares one element and its properties.
struct ElementScan {
    name: String,
    line: usize,
    /// Property names and their lines.
    properties: Vec<(String, usize)>,
}

impl HeaderScan {
    fn element(&self, name: &str) -> Option<&ElementScan> {
        self.elements.iter().find(|e| e.name == name)
    }

    fn element_line(&self, name: &str) -> Option<usize> {
        self.element(name).map(|e| e.line)
    }

    fn property_line(&self, element: &str, property: &str) -> Option<usize> {
        let properties = &self.element(element)?.properties;
        properties.iter().find(|(p, _)| p == property).map(|(_, line)| *line)
    }
}

/// At most 40 characters of `text`, for quoting possibly binary input.
fn quote(text: &str) -> String {
    let mut quoted: String = text.trim().chars().take(40).collect();
    if text.trim().chars().nth(40).is_some() {
        quoted.push_str("...");
    }
    quoted
}

/// Reads the header lines for their numbers, and catches what `ply-rs-bw` would report
/// less precisely: no `ply` line, no `end_header`, a name declared twice.
fn scan_header(bytes: &[u8]) -> Result<HeaderScan, ParseError> {
    let mut lines = TextLines::new(bytes, 1);
    let first = lines.next();
    if first.as_ref().is_none_or(|(_, text)| text.trim() != "ply") {
        let found = first.map(|(_, text)| quote(&text)).unwrap_or_default();
        return Err(ParseError::new(
            Place::Line(1),
            format!("a PLY file starts with a line `ply`, found `{found}`"),
            "check that the file is PLY; export it again",
        ));
    }
    let mut elements: Vec<ElementScan> = Vec::new();
    for (number, text) in lines.by_ref() {
        let mut words = text.split_whitespace();
        match words.next() {
            Some("end_header") => {
                return Ok(HeaderScan {
                    end_line: number,
                    elements,
                });
            }
            Some("element") => {
                let (name, count) = (words.next(), words.next());
                if name.is_none() || count.is_none_or(|c| c.parse::<u64>().is_err()) || words.next().is_some() {
                    return Err(header_line_error(
                        number,
                        &text,
                        "an element line is `element <name> <count>`, the count a whole number",
                    ));
                }
                let name = name.unwrap_or_default().to_owned();
                if let Some(first) = elements.iter().find(|e| e.name == name) {
                    return Err(ParseError::new(
                        Place::Line(number),
                        format!("element `{name}` is declared twice (first on line {})", first.line),
                        "give each element of the header its own name",
                    ));
                }
                elements.push(ElementScan {
                    name,
                    line: number,
                    properties: Vec::new(),
                });
            }
            Some("property") => {
                let rest: Vec<&str> = words.collect();
                let known = |t: &str| SCALAR_TYPES.contains(&t);
                let well_formed = match rest.as_slice() {
                    ["list", count, item, _name] => known(count) && known(item),
                    [kind, _name] => known(kind),
                    _ => false,
                };
                if !well_formed {
                    return Err(header_line_error(
                        number,
                        &text,
                        &format!(
                            "a property line is `property <type> <name>` or `property list <count type> <item type> <name>`, \
                             types among {}",
                            SCALAR_TYPES.join(", ")
                        ),
                    ));
                }
                let name = text.split_whitespace().last().unwrap_or_default().to_owned();
                if let Some(element) = elements.last_mut() {
                    if let Some((_, first_line)) = element.properties.iter().find(|(p, _)| *p == name) {
                        let element = &element.name;
                        return Err(ParseError::new(
                            Place::Line(number),
                            format!(
                                "property `{name}` of element `{element}` is declared twice (first on line {first_line})"
                            ),
                            "give each property of an element its own name",
                        ));
                    }
                    element.properties.push((name, number));
                }
            }
            Some("format") => {
                let encodings = ["ascii", "binary_little_endian", "binary_big_endian"];
                let (encoding, version) = (words.next(), words.next());
                if !encoding.is_some_and(|e| encodings.contains(&e)) || version != Some("1.0") {
                    return Err(header_line_error(
                        number,
                        &text,
                        "the format line is `format ascii 1.0`, `format binary_little_endian 1.0` or \
                         `format binary_big_endian 1.0`",
                    ));
                }
            }
            Some("comment" | "obj_info") | None => {}
            Some(_) => {
                return Err(header_line_error(
                    number,
                    &text,
                    "each header line starts with `format`, `element`, `property`, `comment`, `obj_info` or \
                     `end_header`",
                ));
            }
        }
    }
    let last = lines.last_line().max(1);
    Err(ParseError::new(
        Place::Line(last),
        format!("the header has no `end_header` line (the file ends at line {last})"),
        "the file is truncated or damaged: export it again",
    ))
}

/// The text of a `ply-rs-bw` error, without its line prefix, on one line.
/// The scalar type names of PLY headers.
const SCALAR_TYPES: [&str; 16] = [
    "char", "uchar", "short", "ushort", "int", "uint", "float", "double", "int8", "uint8", "int16", "uint16", "int32",
    "uint32", "float32", "float64",
];

/// A header line this reader cannot read, quoted, with what such a line looks like.
fn header_line_error(line: usize, text: &str, expected: &str) -> ParseError {
    ParseError::new(
        Place::Line(line),
        format!("the header line `{}` cannot be read", quote(text.trim())),
        format!("{expected}; export the model again"),
    )
}

/// The `ply-rs-bw` parser's message in plain words: its debug dump of the grammar's
/// expectations (`Error: ParseError { ... }`) is dropped.
fn ply_message(error: &ply_rs_bw::parser::ParseError) -> String {
    let text = error.to_string();
    let text = match error.line() {
        Some(line) => text
            .strip_prefix(&format!("Line {line}: "))
            .map_or(text.clone(), str::to_owned),
        None => text,
    };
    let text = text.split("Error: ParseError").next().unwrap_or_default().to_string();
    let text = text.replace("Couldn't parse line.", "cannot read the line");
    text.split(['\n', '\t'])
        .map(|part| part.trim().trim_end_matches(';').trim())
        .filter(|part| !part.is_empty())
        .collect::<Vec<_>>()
        .join("; ")
}

/// The properties this reader needs, checked against the header.
struct Layout {
    /// The name of the face index list (`vertex_indices` or `vertex_index`).
    index_list: &'static str,
}

impl Layout {
    fn check(header: &Header, scan: &HeaderScan) -> Result<Self, ParseError> {
        let names = || {
            header
                .elements
                .keys()
                .map(|k| format!("`{k}`"))
                .collect::<Vec<_>>()
                .join(", ")
        };
        let Some(vertex) = header.elements.get("vertex") else {
            return Err(ParseError::new(
                Place::Whole,
                format!(
                    "the header declares no `vertex` element (elements: {})",
                    or_none(&names())
                ),
                "the vertices of a PLY model are the element `vertex` with properties x, y, z; export the model again",
            ));
        };
        let vertex_line = scan.element_line("vertex").unwrap_or(scan.end_line);
        for axis in ["x", "y", "z"] {
            match vertex.properties.get(axis).map(|p| &p.data_type) {
                Some(PropertyType::Scalar(_)) => {}
                Some(PropertyType::List(..)) => {
                    return Err(ParseError::new(
                        Place::Line(scan.property_line("vertex", axis).unwrap_or(vertex_line)),
                        format!("property `{axis}` of element `vertex` is a list; it must be a single number"),
                        "declare the coordinates as `property float x` (likewise y, z)",
                    ));
                }
                None => {
                    return Err(ParseError::new(
                        Place::Line(vertex_line),
                        format!(
                            "element `vertex` has no property `{axis}` (properties: {})",
                            or_none(&property_names(vertex))
                        ),
                        "the vertex element needs the coordinates `property float x`, `y` and `z`",
                    ));
                }
            }
        }
        let Some(face) = header.elements.get("face") else {
            return Err(ParseError::new(
                Place::Whole,
                format!(
                    "the header declares no `face` element (elements: {}): the file holds points, not a surface",
                    names()
                ),
                "export the model as a mesh with faces (element `face`), not as a point cloud or triangle strips",
            ));
        };
        let face_line = scan.element_line("face").unwrap_or(scan.end_line);
        let Some((index_list, property)) = ["vertex_indices", "vertex_index"]
            .into_iter()
            .find_map(|name| face.properties.get(name).map(|p| (name, p)))
        else {
            return Err(ParseError::new(
                Place::Line(face_line),
                format!(
                    "element `face` has no list property `vertex_indices` or `vertex_index` (properties: {})",
                    or_none(&property_names(face))
                ),
                "declare the faces' vertices as `property list uchar int vertex_indices`",
            ));
        };
        let line = Place::Line(scan.property_line("face", index_list).unwrap_or(face_line));
        match &property.data_type {
            PropertyType::List(_, ScalarType::Float | ScalarType::Double) => Err(ParseError::new(
                line,
                format!("property `{index_list}` of element `face` is a list of floating-point numbers"),
                "vertex indices must be integers: declare `property list uchar int vertex_indices`",
            )),
            PropertyType::Scalar(_) => Err(ParseError::new(
                line,
                format!("property `{index_list}` of element `face` is a single number, not a list"),
                "declare the faces' vertices as `property list uchar int vertex_indices`",
            )),
            PropertyType::List(..) => Ok(Self { index_list }),
        }
    }
}

fn or_none(list: &str) -> &str {
    if list.is_empty() { "none" } else { list }
}

fn property_names(element: &ElementDef) -> String {
    element
        .properties
        .keys()
        .map(|k| format!("`{k}`"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// `count` elements named `name`, for messages: "8 vertices", "1 face", "2 `edge` elements".
fn counted(count: usize, name: &str) -> String {
    match (name, count) {
        ("vertex", 1) => "1 vertex".to_owned(),
        ("vertex", _) => format!("{count} vertices"),
        ("face", 1) => "1 face".to_owned(),
        ("face", _) => format!("{count} faces"),
        _ => format!("{count} `{name}` element(s)"),
    }
}

/// The next line that holds something.
fn next_data_line<'a>(lines: &mut TextLines<'a>) -> Option<(usize, std::borrow::Cow<'a, str>)> {
    lines.find(|(_, text)| !text.trim().is_empty())
}

fn read_ascii(
    payload: &[u8],
    header: &Header,
    scan: &HeaderScan,
    layout: &Layout,
    soup: &mut Soup,
) -> Result<(), ParseError> {
    let mut lines = TextLines::new(payload, scan.end_line + 1);
    for (name, element) in &header.elements {
        if element.properties.is_empty() {
            continue;
        }
        let declared_on = scan.element_line(name).unwrap_or(scan.end_line);
        for index in 0..element.count {
            let Some((number, text)) = next_data_line(&mut lines) else {
                let last = lines.last_line().max(1);
                return Err(ParseError::new(
                    Place::Line(last),
                    format!(
                        "the header (line {declared_on}) declares {} but the file ends after {index} of them",
                        counted(element.count, name)
                    ),
                    format!("the file looks truncated: export it again, or correct the count on line {declared_on}"),
                ));
            };
            let place = Place::Line(number);
            let record = ascii_record(&text, name, index, element, layout, place)?;
            soup.take(name, index, record, place)?;
        }
    }
    if let Some((number, text)) = next_data_line(&mut lines) {
        return Err(ParseError::new(
            Place::Line(number),
            format!("`{}` follows the last element declared in the header", quote(&text)),
            "correct the element counts in the header, or delete the extra lines",
        ));
    }
    Ok(())
}

/// Parses one ASCII element line.
fn ascii_record(
    text: &str,
    name: &str,
    index: usize,
    element: &ElementDef,
    layout: &Layout,
    place: Place,
) -> Result<Record, ParseError> {
    let mut tokens = text.split_whitespace();
    let mut record = Record::default();
    let mut used = 0usize;
    let what = format!("{name} {index}");
    let too_few = |property: &str, used: usize| {
        ParseError::new(
            place,
            format!("{what} has {used} value(s), too few: the value of property `{property}` is missing"),
            format!("each `{name}` line holds the properties declared in the header, in order"),
        )
    };
    for (property, definition) in &element.properties {
        let Some(token) = tokens.next() else {
            return Err(too_few(property, used));
        };
        used += 1;
        match &definition.data_type {
            PropertyType::Scalar(_) => {
                let value = parse_f64(token, &format!("property `{property}` of {what}"), place)?;
                let axis = ["x", "y", "z"].iter().position(|a| a == property);
                if let Some(slot) = axis.and_then(|a| record.xyz.get_mut(a)) {
                    *slot = value;
                }
            }
            PropertyType::List(..) => {
                let Ok(length) = token.parse::<usize>() else {
                    return Err(ParseError::new(
                        place,
                        format!("`{token}` is not a list length (expected the length of list `{property}` of {what})"),
                        "a list property is written as its length followed by that many values",
                    ));
                };
                let is_index_list = name == "face" && property == layout.index_list;
                for item in 0..length {
                    let Some(token) = tokens.next() else {
                        return Err(ParseError::new(
                            place,
                            format!(
                                "list `{property}` of {what} declares {length} values but the line holds only {item}"
                            ),
                            "a list property is written as its length followed by that many values",
                        ));
                    };
                    used += 1;
                    if is_index_list {
                        let Ok(vertex) = token.parse::<i64>() else {
                            return Err(ParseError::new(
                                place,
                                format!(
                                    "`{token}` is not a vertex index (value {item} of list `{property}` of {what})"
                                ),
                                "vertex indices are whole numbers counting from 0",
                            ));
                        };
                        record.indices.push(vertex);
                    } else {
                        parse_f64(token, &format!("value {item} of list `{property}` of {what}"), place)?;
                    }
                }
            }
        }
    }
    if let Some(extra) = tokens.next() {
        let extra_count = 1 + tokens.count();
        return Err(ParseError::new(
            place,
            format!(
                "{what} has {extra_count} value(s) more than its properties take, from `{extra}` on (it needs {used})"
            ),
            format!("each `{name}` line holds exactly the properties declared in the header; check the header"),
        ));
    }
    Ok(record)
}

fn read_binary(
    parser: &Parser<Record>,
    bytes: &[u8],
    data_start: u64,
    header: &Header,
    soup: &mut Soup,
) -> Result<(), ParseError> {
    let len = bytes.len() as u64;
    let mut cursor = Cursor::new(bytes);
    cursor.set_position(data_start);
    for (name, element) in &header.elements {
        if element.properties.is_empty() {
            continue;
        }
        for index in 0..element.count {
            let offset = cursor.position();
            let record = match header.encoding {
                Encoding::BinaryBigEndian => parser.read_big_endian_element(&mut cursor, element),
                _ => parser.read_little_endian_element(&mut cursor, element),
            };
            let record = record.map_err(|e| {
                if e.kind() == ErrorKind::UnexpectedEof {
                    ParseError::new(
                        Place::Byte(len),
                        format!(
                            "the header declares {} but the file ends inside {name} {index}",
                            counted(element.count, name)
                        ),
                        "the file is truncated: export or copy it again",
                    )
                } else {
                    ParseError::new(
                        Place::Byte(offset),
                        format!("cannot read {name} {index}: {}", ply_message(&e)),
                        "the file is damaged or its header does not match its data: export it again",
                    )
                }
            })?;
            soup.take(name, index, record, Place::Byte(offset))?;
        }
    }
    let end = cursor.position();
    if end < len {
        return Err(ParseError::new(
            Place::Byte(end),
            format!("{} byte(s) follow the last element declared in the header", len - end),
            "the element counts in the header do not match the data: export the file again",
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::text::testing::{expect_err, read_every_prefix, xorshift};
    use glam::DVec3;

    const CUBE_HEADER: &str = "ply
format ascii 1.0
comment a unit cube
element vertex 8
property float x
property float y
property float z
property uchar red
element face 6
property list uchar int vertex_indices
end_header
";
    const CUBE_VERTICES: [[f32; 3]; 8] = [
        [0., 0., 0.],
        [1., 0., 0.],
        [1., 1., 0.],
        [0., 1., 0.],
        [0., 0., 1.],
        [1., 0., 1.],
        [1., 1., 1.],
        [0., 1., 1.],
    ];
    const CUBE_FACES: [[u8; 4]; 6] = [
        [0, 3, 2, 1],
        [4, 5, 6, 7],
        [0, 1, 5, 4],
        [1, 2, 6, 5],
        [2, 3, 7, 6],
        [3, 0, 4, 7],
    ];

    fn cube_ascii() -> String {
        let mut text = CUBE_HEADER.to_owned();
        for v in CUBE_VERTICES {
            text.push_str(&format!("{} {} {} 255\n", v[0], v[1], v[2]));
        }
        for f in CUBE_FACES {
            text.push_str(&format!("4 {} {} {} {}\n", f[0], f[1], f[2], f[3]));
        }
        text
    }

    fn cube_binary(big_endian: bool) -> Vec<u8> {
        let format = if big_endian {
            "binary_big_endian"
        } else {
            "binary_little_endian"
        };
        let mut bytes = CUBE_HEADER
            .replace("format ascii", &format!("format {format}"))
            .into_bytes();
        for v in CUBE_VERTICES {
            for c in v {
                bytes.extend(if big_endian { c.to_be_bytes() } else { c.to_le_bytes() });
            }
            bytes.push(255);
        }
        for f in CUBE_FACES {
            bytes.push(4);
            for i in f {
                let i = i32::from(i);
                bytes.extend(if big_endian { i.to_be_bytes() } else { i.to_le_bytes() });
            }
        }
        bytes
    }

    fn check_cube(soup: &MeshSoup) {
        assert_eq!(soup.positions.len(), 8);
        assert_eq!(soup.polygons.len(), 6);
        assert_eq!(soup.polygon_noun, "face");
        for (p, v) in soup.positions.iter().zip(CUBE_VERTICES) {
            assert_eq!(*p, DVec3::from_array(v.map(f64::from)));
        }
        for (polygon, f) in soup.polygons.iter().zip(CUBE_FACES) {
            assert_eq!(*polygon, f.map(u32::from).to_vec());
        }
    }

    /// The length of the header, `end_header` line included.
    fn header_len(bytes: &[u8]) -> usize {
        bytes
            .windows(11)
            .position(|w| w == b"end_header\n")
            .map_or(0, |p| p + 11)
    }

    fn err(bytes: &[u8]) -> ParseError {
        expect_err(read(bytes))
    }

    #[test]
    fn reads_ascii_cube() {
        let soup = read(cube_ascii().as_bytes()).unwrap();
        check_cube(&soup);
        assert_eq!(soup.polygon_lines[0], Some(20));
        assert_eq!(soup.polygon_lines[5], Some(25));
    }

    #[test]
    fn reads_binary_cubes() {
        for big_endian in [false, true] {
            let soup = read(cube_binary(big_endian).as_slice()).unwrap();
            check_cube(&soup);
            assert!(soup.polygon_lines.iter().all(Option::is_none));
        }
    }

    #[test]
    fn reads_variants() {
        // Faces before vertices, `vertex_index`, double coordinates, an extra element,
        // CRLF line endings.
        let text = "ply\r\nformat ascii 1.0\r\nelement face 1\r\nproperty list uchar uint vertex_index\r\nelement vertex 3\r\nproperty double z\r\nproperty double y\r\nproperty double x\r\nelement edge 1\r\nproperty int vertex1\r\nproperty int vertex2\r\nend_header\r\n3 2 1 0\r\n1 0 0\r\n2 0 0\r\n3 .5 1e-1\r\n0 1\r\n";
        let soup = read(text.as_bytes()).unwrap();
        assert_eq!(soup.polygons, vec![vec![2, 1, 0]]);
        assert_eq!(soup.positions[2], DVec3::new(0.1, 0.5, 3.0));
        assert_eq!(soup.polygon_lines, vec![Some(13)]);
        // No faces: not a parse error.
        let soup = read("ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n".as_bytes()).unwrap();
        assert!(soup.positions.is_empty() && soup.polygons.is_empty());
    }

    #[test]
    fn missing_elements_and_properties() {
        let e = err(b"ply\nformat ascii 1.0\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n");
        assert_eq!(e.place, Place::Whole);
        assert!(e.problem.contains("no `vertex` element"), "{e}");
        let e = err(b"ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\nend_header\n");
        assert!(
            e.problem.contains("no `face` element") && e.problem.contains("points"),
            "{e}"
        );
        let e = err(b"ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float z\nend_header\n");
        assert_eq!(e.place, Place::Line(3));
        assert!(
            e.problem.contains("no property `y`") && e.problem.contains("`x`, `z`"),
            "{e}"
        );
        let e = err(b"ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\nelement face 0\nproperty list uchar int corners\nend_header\n");
        assert_eq!(e.place, Place::Line(7));
        assert!(
            e.problem.contains("`vertex_indices` or `vertex_index`") && e.problem.contains("`corners`"),
            "{e}"
        );
        let e = err(b"ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\nelement face 0\nproperty list uchar float vertex_indices\nend_header\n");
        assert_eq!(e.place, Place::Line(8));
        assert!(e.problem.contains("floating-point"), "{e}");
        let e = err(b"ply\nformat ascii 1.0\nelement vertex 0\nproperty list uchar float x\nproperty float y\nproperty float z\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n");
        assert_eq!(e.place, Place::Line(4));
        assert!(e.problem.contains("is a list"), "{e}");
    }

    #[test]
    fn bad_headers() {
        let e = err(b"PLY\n");
        assert_eq!(e.place, Place::Line(1));
        let e = err(b"ply\nformat ascii 1.0\nelement vertex 1\n");
        assert_eq!(e.place, Place::Line(3));
        assert!(e.problem.contains("no `end_header`"), "{e}");
        let e = err(b"ply\nformat ascii 1.0\nelemnt vertex 1\nend_header\n");
        assert_eq!(e.place, Place::Line(3));
        assert!(e.problem.contains("`elemnt vertex 1` cannot be read"), "{e}");
        assert!(e.fix.contains("each header line starts with"), "{e}");
        for (text, line, fix) in [
            (
                &b"ply\nformat ascii 1.0\nelement vertex 1\nproperty flot x\nend_header\n"[..],
                4,
                "property <type> <name>",
            ),
            (b"ply\nformat ascii 2.0\nend_header\n", 2, "format ascii 1.0"),
            (
                b"ply\nformat ascii 1.0\nelement vertex x\nend_header\n",
                3,
                "the count a whole number",
            ),
            (
                b"ply\nformat ascii 1.0\nelement vertex 1\nproperty list uchar x\nend_header\n",
                4,
                "property list",
            ),
        ] {
            let e = err(text);
            assert_eq!(e.place, Place::Line(line), "{e}");
            assert!(e.fix.contains(fix), "{e}");
            assert!(!format!("{e}").contains("ParseError"), "{e}");
        }
        let e = err(b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float x\nend_header\n");
        assert_eq!(e.place, Place::Line(5));
        assert!(e.problem.contains("declared twice (first on line 4)"), "{e}");
    }

    #[test]
    fn ascii_value_errors() {
        let good = cube_ascii();
        let with = |n: usize, replacement: &str| {
            let mut lines: Vec<&str> = good.lines().collect();
            lines[n - 1] = replacement;
            lines.join("\n")
        };
        // Line 12 is vertex 0, line 20 face 0.
        let e = err(with(14, "1 one 0 255").as_bytes());
        assert_eq!(e.place, Place::Line(14));
        assert!(
            e.problem.contains("`one`") && e.problem.contains("property `y` of vertex 2"),
            "{e}"
        );
        let e = err(with(14, "1 nan 0 255").as_bytes());
        assert_eq!(e.place, Place::Line(14));
        assert!(
            e.problem.starts_with("vertex 2:") && e.problem.contains("not finite"),
            "{e}"
        );
        let e = err(with(14, "1 1 0").as_bytes());
        assert!(
            e.problem.contains("vertex 2 has 3 value(s), too few") && e.problem.contains("`red`"),
            "{e}"
        );
        let e = err(with(14, "1 1 0 255 7").as_bytes());
        assert!(
            e.problem.contains("1 value(s) more") && e.problem.contains("`7`"),
            "{e}"
        );
        let e = err(with(21, "4 4 5 6").as_bytes());
        assert_eq!(e.place, Place::Line(21));
        assert!(e.problem.contains("declares 4 values but the line holds only 3"), "{e}");
        let e = err(with(21, "4 4 5 6 8").as_bytes());
        assert_eq!(e.place, Place::Line(21));
        assert!(
            e.problem
                .contains("face 1 refers to vertex 8 but the file has 8 vertices"),
            "{e}"
        );
        let e = err(with(21, "4 4 5 -6 7").as_bytes());
        assert!(e.problem.contains("vertex -6") && e.problem.contains("negative"), "{e}");
        let e = err(with(21, "2 4 5").as_bytes());
        assert!(e.problem.contains("face 1 has 2 vertices"), "{e}");
        let e = err(with(21, "4 4 5 6 x").as_bytes());
        assert!(e.problem.contains("`x` is not a vertex index"), "{e}");
        let e = err(with(21, "four 4 5 6 7").as_bytes());
        assert!(e.problem.contains("`four` is not a list length"), "{e}");
        let e = err(format!("{good}3 0 1 2\n").as_bytes());
        assert_eq!(e.place, Place::Line(26));
        assert!(e.problem.contains("follows the last element"), "{e}");
    }

    #[test]
    fn truncated_files() {
        let good = cube_ascii();
        let cut: String = good.lines().take(15).map(|l| format!("{l}\n")).collect();
        let e = err(cut.as_bytes());
        assert_eq!(e.place, Place::Line(15));
        assert!(
            e.problem
                .contains("declares 8 vertices but the file ends after 4 of them"),
            "{e}"
        );
        let binary = cube_binary(false);
        let e = err(&binary[..binary.len() - 3]);
        assert_eq!(e.place, Place::Byte(binary.len() as u64 - 3));
        assert!(
            e.problem.contains("declares 6 faces") && e.problem.contains("inside face 5"),
            "{e}"
        );
        let mut padded = binary.clone();
        padded.extend_from_slice(b"xyz");
        let e = err(&padded);
        assert_eq!(e.place, Place::Byte(binary.len() as u64));
        assert!(e.problem.contains("3 byte(s) follow"), "{e}");
    }

    #[test]
    fn binary_value_errors() {
        let mut bytes = cube_binary(false);
        let vertex3 = header_len(&bytes) + 3 * 13;
        // Vertex 3's z (records of 13 bytes).
        let at = vertex3 + 8;
        bytes[at..at + 4].copy_from_slice(&f32::INFINITY.to_le_bytes());
        let e = err(&bytes);
        assert_eq!(e.place, Place::Byte(vertex3 as u64));
        assert!(
            e.problem.starts_with("vertex 3:") && e.problem.contains("not finite"),
            "{e}"
        );
        let mut bytes = cube_binary(true);
        // Face 2's third index (records of 17 bytes after 8 × 13 vertex bytes).
        let face2 = header_len(&bytes) + 8 * 13 + 2 * 17;
        bytes[face2 + 9..face2 + 13].copy_from_slice(&9i32.to_be_bytes());
        let e = err(&bytes);
        assert_eq!(e.place, Place::Byte(face2 as u64));
        assert!(
            e.problem
                .contains("face 2 refers to vertex 9 but the file has 8 vertices"),
            "{e}"
        );
        bytes[face2 + 9..face2 + 13].copy_from_slice(&(-2i32).to_be_bytes());
        let e = err(&bytes);
        assert!(e.problem.contains("vertex -2"), "{e}");
    }

    #[test]
    fn huge_declared_counts_do_not_allocate() {
        let text = "ply\nformat binary_little_endian 1.0\nelement vertex 18446744073709551615\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uint int vertex_indices\nend_header\n";
        let e = err(text.as_bytes());
        assert!(e.problem.contains("ends inside vertex 0"), "{e}");
        let mut bytes = "ply\nformat binary_little_endian 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uint int vertex_indices\nend_header\n".as_bytes().to_vec();
        bytes.extend(u32::MAX.to_le_bytes());
        let e = err(&bytes);
        assert!(
            e.problem.contains("declares 1 face but the file ends inside face 0"),
            "{e}"
        );
    }

    #[test]
    fn never_panics_on_prefixes_and_garbage() {
        let ascii = cube_ascii();
        read_every_prefix(|b| read(b), ascii.as_bytes());
        for big_endian in [false, true] {
            let binary = cube_binary(big_endian);
            read_every_prefix(|b| read(b), &binary);
        }
        let mut state = 0xda94_2042_e4dd_58b5_u64;
        let headers = [
            cube_binary(false),
            cube_binary(true),
            cube_ascii().into_bytes(),
            Vec::new(),
        ];
        for round in 0..400 {
            let template = &headers[round % headers.len()];
            let keep = header_len(template);
            let mut garbage = template[..keep].to_vec();
            for _ in 0..(round % 157) {
                xorshift(&mut state);
                garbage.push(if round % 8 == 2 {
                    b"0123456789 -\n"[(state % 13) as usize]
                } else {
                    state as u8
                });
            }
            let _ = read(garbage.as_slice());
        }
    }
}
