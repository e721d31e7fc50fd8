//! Element ids: small `Copy` handles into a [`Part`](crate::model::Part)'s arrays,
//! usable as hash keys (in the spirit of parry's `FeatureId`).

use std::fmt;

macro_rules! element_id {
    ($(#[$doc:meta])* $name:ident, $prefix:literal) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
        pub struct $name(pub u32);

        impl $name {
            /// The index into the part's array of this kind of element.
            #[must_use]
            pub fn index(self) -> usize {
                self.0 as usize
            }
        }

        impl fmt::Display for $name {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                write!(f, concat!($prefix, "{}"), self.0)
            }
        }
    };
}

element_id!(
    /// A face of a part, displayed as `f3`.
    FaceId,
    "f"
);
element_id!(
    /// An edge of a part, displayed as `e5`.
    EdgeId,
    "e"
);
element_id!(
    /// A vertex of a part, displayed as `v7`.
    VertexId,
    "v"
);

/// Any surface element of a part.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum ElementId {
    /// A face.
    Face(FaceId),
    /// An edge.
    Edge(EdgeId),
    /// A vertex.
    Vertex(VertexId),
}

impl ElementId {
    /// The element's dimension: 2 for a face, 1 for an edge, 0 for a vertex.
    #[must_use]
    pub fn dimension(self) -> u8 {
        match self {
            ElementId::Vertex(_) => 0,
            ElementId::Edge(_) => 1,
            ElementId::Face(_) => 2,
        }
    }

    /// Whether the element is a face.
    #[must_use]
    pub fn is_face(self) -> bool {
        matches!(self, ElementId::Face(_))
    }

    /// Whether the element is an edge.
    #[must_use]
    pub fn is_edge(self) -> bool {
        matches!(self, ElementId::Edge(_))
    }

    /// Whether the element is a vertex.
    #[must_use]
    pub fn is_vertex(self) -> bool {
        matches!(self, ElementId::Vertex(_))
    }
}

impl fmt::Display for ElementId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ElementId::Face(id) => id.fmt(f),
            ElementId::Edge(id) => id.fmt(f),
            ElementId::Vertex(id) => id.fmt(f),
        }
    }
}

impl std::str::FromStr for ElementId {
    type Err = String;

    /// Parses `f3`, `e5` or `v7`.
    fn from_str(text: &str) -> Result<ElementId, String> {
        let bad = || format!("bad element id {text:?} (expected f, e or v followed by a number, e.g. f3)");
        let mut chars = text.chars();
        let kind = chars.next().ok_or_else(bad)?;
        let digits = chars.as_str();
        if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
            return Err(bad());
        }
        let index: u32 = digits.parse().map_err(|_| bad())?;
        match kind {
            'f' => Ok(ElementId::Face(FaceId(index))),
            'e' => Ok(ElementId::Edge(EdgeId(index))),
            'v' => Ok(ElementId::Vertex(VertexId(index))),
            _ => Err(bad()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ids_parse_back_from_their_display() {
        for id in [
            ElementId::Face(FaceId(3)),
            ElementId::Edge(EdgeId(0)),
            ElementId::Vertex(VertexId(4_000_000)),
        ] {
            assert_eq!(id.to_string().parse::<ElementId>(), Ok(id));
        }
        for bad in ["", "f", "x3", "f-1", "f 3", "F3", "f3a", "f99999999999"] {
            assert!(bad.parse::<ElementId>().is_err(), "{bad}");
        }
    }

    #[test]
    fn dimension_and_kind_agree() {
        let ids = [
            ElementId::Vertex(VertexId(0)),
            ElementId::Edge(EdgeId(0)),
            ElementId::Face(FaceId(0)),
        ];
        for (d, id) in ids.into_iter().enumerate() {
            assert_eq!(usize::from(id.dimension()), d);
            assert_eq!([id.is_vertex(), id.is_edge(), id.is_face()], [d == 0, d == 1, d == 2]);
        }
    }

    #[test]
    fn ids_display_with_their_kind_prefix() {
        assert_eq!(FaceId(3).to_string(), "f3");
        assert_eq!(ElementId::Edge(EdgeId(5)).to_string(), "e5");
        assert_eq!(ElementId::Vertex(VertexId(7)).to_string(), "v7");
    }
}
