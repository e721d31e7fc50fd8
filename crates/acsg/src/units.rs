//! Length units. A mesh (OFF, OBJ, STL, PLY) has no unit: its numbers are whatever the
//! exporting program wrote, and the user says which unit that is (`--units`, or the
//! task file's `units` key). A CAD file (STEP, IGES) states its unit, and its
//! coordinates are converted to the unit of the run (millimetres when none is given).
//! Bounds and every length printed or written are in the unit of the run; angles are
//! degrees wherever a user types or reads them, radians in JSON files.

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

/// A length unit a run can be in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum LengthUnit {
    /// Millimetres.
    Mm,
    /// Centimetres.
    Cm,
    /// Metres.
    M,
    /// Inches.
    In,
}

/// A unit name that is not one of [`LengthUnit`]'s.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("unknown length unit '{0}' (give mm, cm, m or in)")]
pub struct UnitError(pub String);

impl LengthUnit {
    /// Every unit, in the order of the help text.
    pub const ALL: [LengthUnit; 4] = [LengthUnit::Mm, LengthUnit::Cm, LengthUnit::M, LengthUnit::In];

    /// Millimetres in one of this unit.
    ///
    /// ```
    /// assert_eq!(acsg::units::LengthUnit::In.millimetres(), 25.4);
    /// ```
    #[must_use]
    pub fn millimetres(self) -> f64 {
        match self {
            LengthUnit::Mm => 1.0,
            LengthUnit::Cm => 10.0,
            LengthUnit::M => 1000.0,
            LengthUnit::In => 25.4,
        }
    }

    /// The unit's symbol: `mm`, `cm`, `m` or `in`.
    #[must_use]
    pub fn symbol(self) -> &'static str {
        match self {
            LengthUnit::Mm => "mm",
            LengthUnit::Cm => "cm",
            LengthUnit::M => "m",
            LengthUnit::In => "in",
        }
    }
}

impl fmt::Display for LengthUnit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.symbol())
    }
}

impl FromStr for LengthUnit {
    type Err = UnitError;

    /// Reads `mm`, `cm`, `m` or `in` (also `inch`, `inches`, `millimetre(s)`, ...;
    /// case ignored).
    ///
    /// ```
    /// use acsg::units::LengthUnit;
    /// assert_eq!("MM".parse::<LengthUnit>(), Ok(LengthUnit::Mm));
    /// assert_eq!("inch".parse::<LengthUnit>(), Ok(LengthUnit::In));
    /// assert!("ft".parse::<LengthUnit>().is_err());
    /// ```
    fn from_str(text: &str) -> Result<Self, Self::Err> {
        match text.trim().to_ascii_lowercase().as_str() {
            "mm" | "millimetre" | "millimetres" | "millimeter" | "millimeters" => Ok(LengthUnit::Mm),
            "cm" | "centimetre" | "centimetres" | "centimeter" | "centimeters" => Ok(LengthUnit::Cm),
            "m" | "metre" | "metres" | "meter" | "meters" => Ok(LengthUnit::M),
            "in" | "inch" | "inches" => Ok(LengthUnit::In),
            _ => Err(UnitError(text.to_string())),
        }
    }
}

/// How lengths are labelled when no unit was given.
pub const UNSPECIFIED: &str = "model units";

/// The label of a run's lengths: the unit's symbol, or [`UNSPECIFIED`].
#[must_use]
pub fn label(unit: Option<LengthUnit>) -> String {
    unit.map_or_else(|| UNSPECIFIED.to_string(), |u| u.symbol().to_string())
}
