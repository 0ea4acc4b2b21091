//! Values of a scene that may vary over the body: a number, a formula of the position (and of
//! the pseudo-time `t` of a load history), or, from Rust, a function.

use std::fmt;
use std::sync::Arc;

use serde::{Deserialize, Deserializer, Serialize, Serializer};
use vem_mesh::expression::Expression;

/// A function of the coordinates `x` (length the dimension) and the pseudo-time `t`.
pub type ScalarFunction = Arc<dyn Fn(&[f64], f64) -> f64 + Send + Sync>;

/// A vector function of the position and the pseudo-time (from Rust).
pub type VectorFunction = Arc<dyn Fn(&[f64], f64) -> Vec<f64> + Send + Sync>;

/// A scalar of a scene: a number, an expression of `x, y, z, t` written as a string, or a
/// function (Rust only; it does not serialise).
///
/// ```
/// use vem_scene::ScalarValue;
/// let v: ScalarValue = serde_json::from_str(r#""0.01 * x""#)?;
/// assert_eq!(v.at(&[2.0, 0.0], 1.0), 0.02);
/// let c: ScalarValue = serde_json::from_str("0.5")?;
/// assert_eq!((c.at(&[9.0, 9.0], 1.0), c.constant()), (0.5, Some(0.5)));
/// # Ok::<(), serde_json::Error>(())
/// ```
#[derive(Clone)]
pub enum ScalarValue {
    /// A number.
    Constant(f64),
    /// A formula of the position and the pseudo-time.
    Expression(Expression),
    /// A function of the position and the pseudo-time.
    Function(ScalarFunction),
}

impl ScalarValue {
    /// A function of the coordinates and the pseudo-time.
    pub fn function(f: impl Fn(&[f64], f64) -> f64 + Send + Sync + 'static) -> Self {
        Self::Function(Arc::new(f))
    }

    /// The value at the point `x` and pseudo-time `t`.
    pub fn at(&self, x: &[f64], t: f64) -> f64 {
        match self {
            ScalarValue::Constant(v) => *v,
            ScalarValue::Expression(e) => e.eval_at(x, t),
            ScalarValue::Function(f) => f(x, t),
        }
    }

    /// The number, when the value is one.
    pub fn constant(&self) -> Option<f64> {
        match self {
            ScalarValue::Constant(v) => Some(*v),
            _ => None,
        }
    }

    /// The highest coordinate an expression uses (see [`Expression::dimension_used`]; 0 for
    /// a number or a function).
    pub fn dimension_used(&self) -> usize {
        match self {
            ScalarValue::Expression(e) => e.dimension_used(),
            _ => 0,
        }
    }

    /// Whether an expression uses the pseudo-time.
    pub fn uses_time(&self) -> bool {
        matches!(self, ScalarValue::Expression(e) if e.uses_time())
    }
}

impl From<f64> for ScalarValue {
    fn from(v: f64) -> Self {
        ScalarValue::Constant(v)
    }
}

impl fmt::Debug for ScalarValue {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ScalarValue::Constant(v) => write!(f, "{v}"),
            ScalarValue::Expression(e) => write!(f, "{:?}", e.source()),
            ScalarValue::Function(_) => write!(f, "<function>"),
        }
    }
}

impl fmt::Display for ScalarValue {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ScalarValue::Constant(v) => write!(f, "{v}"),
            ScalarValue::Expression(e) => write!(f, "\"{}\"", e.source()),
            ScalarValue::Function(_) => write!(f, "<function>"),
        }
    }
}

impl<'de> Deserialize<'de> for ScalarValue {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct Visitor;
        impl serde::de::Visitor<'_> for Visitor {
            type Value = ScalarValue;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("a number or an expression of x, y, z, t (a string)")
            }
            fn visit_f64<E: serde::de::Error>(self, v: f64) -> Result<Self::Value, E> {
                Ok(ScalarValue::Constant(v))
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<Self::Value, E> {
                Ok(ScalarValue::Constant(v as f64))
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<Self::Value, E> {
                Ok(ScalarValue::Constant(v as f64))
            }
            fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<Self::Value, E> {
                Expression::parse(v)
                    .map(ScalarValue::Expression)
                    .map_err(E::custom)
            }
        }
        deserializer.deserialize_any(Visitor)
    }
}

impl Serialize for ScalarValue {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        match self {
            ScalarValue::Constant(v) => serializer.serialize_f64(*v),
            ScalarValue::Expression(e) => serializer.serialize_str(e.source()),
            ScalarValue::Function(_) => Err(serde::ser::Error::custom(
                "a function of the position does not serialise: give a number or an expression",
            )),
        }
    }
}

/// A vector of a scene: one [`ScalarValue`] per component, or a function (Rust only).
#[derive(Clone)]
pub enum VectorValue {
    /// Its components.
    Components(Vec<ScalarValue>),
    /// A function of the position and the pseudo-time, returning the components.
    Function(VectorFunction),
}

impl VectorValue {
    /// A constant vector.
    pub fn constant(components: &[f64]) -> Self {
        Self::Components(components.iter().map(|&v| v.into()).collect())
    }

    /// A function of the coordinates and the pseudo-time.
    pub fn function(f: impl Fn(&[f64], f64) -> Vec<f64> + Send + Sync + 'static) -> Self {
        Self::Function(Arc::new(f))
    }

    /// The number of components given (`None` for a function).
    pub fn len(&self) -> Option<usize> {
        match self {
            VectorValue::Components(c) => Some(c.len()),
            VectorValue::Function(_) => None,
        }
    }

    /// Whether no component is given.
    pub fn is_empty(&self) -> bool {
        self.len() == Some(0)
    }

    /// The components, when given one by one.
    pub fn components(&self) -> Option<&[ScalarValue]> {
        match self {
            VectorValue::Components(c) => Some(c),
            VectorValue::Function(_) => None,
        }
    }

    /// Component `k` at `x` and `t` (zero beyond the components given).
    pub fn at(&self, x: &[f64], t: f64, k: usize) -> f64 {
        match self {
            VectorValue::Components(c) => c.get(k).map_or(0.0, |v| v.at(x, t)),
            VectorValue::Function(f) => f(x, t).get(k).copied().unwrap_or(f64::NAN),
        }
    }
}

impl fmt::Debug for VectorValue {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            VectorValue::Components(c) => f.debug_list().entries(c).finish(),
            VectorValue::Function(_) => write!(f, "<function>"),
        }
    }
}

impl<'de> Deserialize<'de> for VectorValue {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        Vec::<ScalarValue>::deserialize(deserializer).map(VectorValue::Components)
    }
}

impl Serialize for VectorValue {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        match self {
            VectorValue::Components(c) => c.serialize(serializer),
            VectorValue::Function(_) => Err(serde::ser::Error::custom(
                "a function of the position does not serialise: give numbers or expressions",
            )),
        }
    }
}
