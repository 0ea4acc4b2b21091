//! Registries: the one list of names the CLI, the studies, Python and a user's program share,
//! for elements and stabilisations here and for contact solvers and laws in `vem-contact`.
//!
//! A [`Registry`] maps a name to a one-line summary and a factory that builds the item from a
//! table of settings ([`Options`]): each factory deserialises its own settings, so a new setting
//! is a field of the item's settings type, and an unknown setting is refused with its path. A
//! user's own item joins a registry with [`Registry::register`] and is then available by name
//! wherever the registry is passed (scene files, studies).

use std::fmt;
use std::sync::Arc;

use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::{
    BBar, DRecipe, DofiDofi, ElementSpace, LinearTetrahedron, LinearTriangle, LowestOrderVem,
    Options, OptionsError, PolyhedralElement, PolyhedralStabilisation, PolyhedralVem,
    Stabilisation, StabilisationScaling,
};

/// What can go wrong with a registry of names.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum RegistryError {
    /// No entry has this name.
    #[error("unknown {kind} '{name}' (known: {})", known.join(", "))]
    UnknownName {
        /// What is looked up ("element", "solver", ...).
        kind: &'static str,
        /// The name asked for.
        name: String,
        /// The registered names, in registration order.
        known: Vec<String>,
    },
    /// An entry with this name exists already.
    #[error("{kind} '{name}' is registered already")]
    DuplicateName {
        /// What is registered ("element", "solver", ...).
        kind: &'static str,
        /// The name.
        name: String,
    },
    /// A name must be non-empty and made of ASCII letters, digits, `-` and `_`.
    #[error("invalid {kind} name '{name}': use ASCII letters, digits, '-' and '_'")]
    InvalidName {
        /// What is registered ("element", "solver", ...).
        kind: &'static str,
        /// The name.
        name: String,
    },
    /// The item refused its settings.
    #[error("{kind} '{name}': {source}")]
    Options {
        /// What is made ("element", "solver", ...).
        kind: &'static str,
        /// Its name.
        name: String,
        /// The refused setting, with its path inside the settings table.
        #[source]
        source: OptionsError,
    },
}

impl RegistryError {
    /// The path of the refused setting inside the item's settings table, when the error is
    /// about one.
    pub fn option_path(&self) -> Option<&str> {
        match self {
            RegistryError::Options { source, .. } => Some(&source.path),
            _ => None,
        }
    }
}

/// A name with its settings, as scene files and dicts write a choice from a registry: the
/// name alone (`"penalty"`) or a table with the name and the settings
/// (`{ name = "penalty", tolerance = 1e-8 }`).
///
/// ```
/// use vem_space::Choice;
/// let plain: Choice = serde_json::from_str(r#""vem1-bbar""#)?;
/// assert_eq!((plain.name.as_str(), plain.options.is_empty()), ("vem1-bbar", true));
/// let table: Choice = serde_json::from_str(r#"{ "name": "vem1", "stabilisation": "drecipe" }"#)?;
/// assert_eq!(table.name, "vem1");
/// assert_eq!(table.options.get("stabilisation").unwrap(), "drecipe");
/// # Ok::<(), serde_json::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Choice {
    /// The registered name.
    pub name: String,
    /// Its settings (empty: the defaults).
    pub options: Options,
}

impl Choice {
    /// `name` with default settings.
    pub fn named(name: impl Into<String>) -> Self {
        Self {
            name: name.into(),
            options: Options::new(),
        }
    }

    /// `name` with the settings `options`.
    pub fn with_options(name: impl Into<String>, options: Options) -> Self {
        Self {
            name: name.into(),
            options,
        }
    }
}

impl<'de> Deserialize<'de> for Choice {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        use serde::de::Error;
        match serde_json::Value::deserialize(deserializer)? {
            serde_json::Value::String(name) => Ok(Self::named(name)),
            serde_json::Value::Object(mut table) => {
                let name = match table.remove("name") {
                    Some(serde_json::Value::String(name)) => name,
                    Some(other) => {
                        return Err(D::Error::custom(format!(
                            "`name` must be a string, found {other}"
                        )))
                    }
                    None => return Err(D::Error::custom("missing field `name`")),
                };
                Ok(Self {
                    name,
                    options: Options::from_value(serde_json::Value::Object(table))
                        .map_err(D::Error::custom)?,
                })
            }
            other => Err(D::Error::custom(format!(
                "expected a name or a table with `name` and settings, found {other}"
            ))),
        }
    }
}

impl Serialize for Choice {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        if self.options.is_empty() {
            return serializer.serialize_str(&self.name);
        }
        let mut table = match self.options.to_value() {
            serde_json::Value::Object(map) => map,
            _ => serde_json::Map::new(),
        };
        table.insert("name".into(), serde_json::Value::String(self.name.clone()));
        table.serialize(serializer)
    }
}

/// A factory of a registry: the item from its settings, given the registry's context `C`.
pub type Factory<T, C = ()> = Arc<dyn Fn(&Options, &C) -> Result<T, OptionsError> + Send + Sync>;

struct Entry<T, C> {
    name: String,
    summary: String,
    factory: Factory<T, C>,
}

impl<T, C> Clone for Entry<T, C> {
    fn clone(&self) -> Self {
        Self {
            name: self.name.clone(),
            summary: self.summary.clone(),
            factory: Arc::clone(&self.factory),
        }
    }
}

/// Items of type `T` by name (see the module docs); factories see a context `C` (the element
/// registry passes its stabilisations).
pub struct Registry<T, C = ()> {
    kind: &'static str,
    entries: Vec<Entry<T, C>>,
}

impl<T, C> Clone for Registry<T, C> {
    fn clone(&self) -> Self {
        Self {
            kind: self.kind,
            entries: self.entries.clone(),
        }
    }
}

impl<T, C> fmt::Debug for Registry<T, C> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_map()
            .entries(self.entries.iter().map(|e| (&e.name, &e.summary)))
            .finish()
    }
}

impl<T, C> Registry<T, C> {
    /// A registry of `kind` ("element", "solver", ...) without any entry.
    pub fn empty(kind: &'static str) -> Self {
        Self {
            kind,
            entries: Vec::new(),
        }
    }

    /// What the registry holds ("element", "solver", ...).
    pub fn kind(&self) -> &'static str {
        self.kind
    }

    /// Adds `name` with a one-line `summary`, built from its settings by `factory`. The name
    /// must be new, non-empty and made of ASCII letters, digits, `-` and `_`.
    ///
    /// # Errors
    /// [`RegistryError::InvalidName`], [`RegistryError::DuplicateName`].
    pub fn register_with(
        &mut self,
        name: impl Into<String>,
        summary: impl Into<String>,
        factory: impl Fn(&Options, &C) -> Result<T, OptionsError> + Send + Sync + 'static,
    ) -> Result<&mut Self, RegistryError> {
        let name = name.into();
        if name.is_empty()
            || !name
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_')
        {
            return Err(RegistryError::InvalidName {
                kind: self.kind,
                name,
            });
        }
        if self.contains(&name) {
            return Err(RegistryError::DuplicateName {
                kind: self.kind,
                name,
            });
        }
        self.entries.push(Entry {
            name,
            summary: summary.into(),
            factory: Arc::new(factory),
        });
        Ok(self)
    }

    /// The registered names, in registration order.
    pub fn names(&self) -> Vec<&str> {
        self.entries.iter().map(|e| e.name.as_str()).collect()
    }

    /// Whether `name` is registered.
    pub fn contains(&self, name: &str) -> bool {
        self.entries.iter().any(|e| e.name == name)
    }

    /// The one-line summary of `name`, if registered.
    pub fn summary(&self, name: &str) -> Option<&str> {
        self.entry(name).map(|e| e.summary.as_str())
    }

    fn entry(&self, name: &str) -> Option<&Entry<T, C>> {
        self.entries.iter().find(|e| e.name == name)
    }

    /// The item `name` built with `options` in the context `context`.
    ///
    /// # Errors
    /// [`RegistryError::UnknownName`] listing the known names, [`RegistryError::Options`]
    /// naming the refused setting.
    pub fn make_in(&self, name: &str, options: &Options, context: &C) -> Result<T, RegistryError> {
        let entry = self.entry(name).ok_or_else(|| RegistryError::UnknownName {
            kind: self.kind,
            name: name.to_string(),
            known: self.entries.iter().map(|e| e.name.clone()).collect(),
        })?;
        (entry.factory)(options, context).map_err(|source| RegistryError::Options {
            kind: self.kind,
            name: name.to_string(),
            source,
        })
    }
}

impl<T> Registry<T, ()> {
    /// Adds `name` built from its settings by `factory` (see [`Registry::register_with`]).
    ///
    /// # Errors
    /// As [`Registry::register_with`].
    pub fn register(
        &mut self,
        name: impl Into<String>,
        summary: impl Into<String>,
        factory: impl Fn(&Options) -> Result<T, OptionsError> + Send + Sync + 'static,
    ) -> Result<&mut Self, RegistryError> {
        self.register_with(name, summary, move |options, _| factory(options))
    }

    /// The item `name` built with `options`.
    ///
    /// # Errors
    /// As [`Registry::make_in`].
    pub fn make(&self, name: &str, options: &Options) -> Result<T, RegistryError> {
        self.make_in(name, options, &())
    }

    /// The item of a [`Choice`].
    ///
    /// # Errors
    /// As [`Registry::make_in`].
    pub fn make_choice(&self, choice: &Choice) -> Result<T, RegistryError> {
        self.make(&choice.name, &choice.options)
    }
}

/// Stabilisations of the lowest-order VEM by name: `"dofi-dofi"` (settings `scaling = "trace"
/// | "shear"`, `scale`), `"drecipe"`, `"bbar"`.
pub type StabilisationRegistry = Registry<Arc<dyn Stabilisation>>;

/// The settings of the dofi-dofi stabilisation.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct DofiDofiSettings {
    #[serde(default)]
    scaling: Option<ScalingName>,
    #[serde(default)]
    scale: Option<f64>,
}

#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(rename_all = "kebab-case")]
enum ScalingName {
    Trace,
    Shear,
}

impl Registry<Arc<dyn Stabilisation>> {
    /// The name of the default stabilisation, dofi-dofi scaled by `trace(C)/8`.
    pub const DEFAULT_STABILISATION: &'static str = "dofi-dofi";

    /// The stabilisations of this crate.
    pub fn builtin_stabilisations() -> Self {
        builtin_stabilisations_of(
            [
                "S = alpha I, alpha = scale * trace(C) (scaling \"trace\", the default) or scale * 5 mu (\"shear\"); scale 1/8",
                "S = diag(K_c) (Beirao da Veiga, Dassi, Russo 2017)",
                "locking-free: alpha = min(trace(C), 3 trace(C_dev))/8",
            ],
            |s| Arc::new(s) as Arc<dyn Stabilisation>,
            || Arc::new(DRecipe) as Arc<dyn Stabilisation>,
            || Arc::new(BBar) as Arc<dyn Stabilisation>,
        )
    }
}

/// Stabilisations of the lowest-order VEM on polyhedra by name: the same names and settings as
/// [`StabilisationRegistry`], with their three-dimensional scalings
/// ([`crate::PolyhedralStabilisation`]).
pub type PolyhedralStabilisationRegistry = Registry<Arc<dyn PolyhedralStabilisation>>;

impl Registry<Arc<dyn PolyhedralStabilisation>> {
    /// The stabilisations of this crate on polyhedra: `"dofi-dofi"` (settings `scaling`,
    /// `scale`), `"drecipe"`, `"bbar"`.
    pub fn builtin_polyhedral_stabilisations() -> Self {
        builtin_stabilisations_of(
            [
                "S = alpha I, alpha = scale * trace(C) l_E/6 (scaling \"trace\", the default) or scale * 9 mu l_E/6 (\"shear\"); scale 1/8, l_E = h_E/sqrt(3)",
                "S_ii = max(K_c,ii, floor): the D-recipe on polyhedra",
                "locking-free: alpha = min(trace(C), 3 trace(C_dev)) l_E/48",
            ],
            |s| Arc::new(s) as Arc<dyn PolyhedralStabilisation>,
            || Arc::new(DRecipe) as Arc<dyn PolyhedralStabilisation>,
            || Arc::new(BBar) as Arc<dyn PolyhedralStabilisation>,
        )
    }
}

/// The three built-in stabilisations as items of type `T` (2D or 3D trait objects), with
/// their summaries in the order dofi-dofi, drecipe, bbar.
fn builtin_stabilisations_of<T: 'static>(
    summaries: [&'static str; 3],
    dofi: fn(DofiDofi) -> T,
    drecipe: fn() -> T,
    bbar: fn() -> T,
) -> Registry<T> {
    let mut registry = Registry::empty("stabilisation");
    let [dofi_summary, drecipe_summary, bbar_summary] = summaries;
    registry
        .register_with("dofi-dofi", dofi_summary, move |o: &Options, _: &()| {
            let s: DofiDofiSettings = o.parse()?;
            let scaling = match s.scaling {
                None | Some(ScalingName::Trace) => StabilisationScaling::TraceOfC,
                Some(ScalingName::Shear) => StabilisationScaling::ShearModulus,
            };
            let scale = s.scale.unwrap_or(DofiDofi::DEFAULT_SCALE);
            let made = DofiDofi::try_new(scaling, scale)
                .map_err(|e| OptionsError::at("scale", e.to_string()))?;
            Ok(dofi(made))
        })
        .and_then(|r| {
            r.register_with("drecipe", drecipe_summary, move |o: &Options, _: &()| {
                o.refuse_all("the D-recipe")?;
                Ok(drecipe())
            })
        })
        .and_then(|r| {
            r.register_with("bbar", bbar_summary, move |o: &Options, _: &()| {
                o.refuse_all("bbar")?;
                Ok(bbar())
            })
        })
        .expect("built-in names are valid and distinct");
    registry
}

/// Element types by name, each with a one-line summary and a factory from settings; the
/// lowest-order VEM takes its stabilisation from the registry's stabilisations (settings
/// `stabilisation = "<name>"` or `{ name = "<name>", ... }`).
///
/// ```
/// use std::sync::Arc;
/// use vem_space::{ElementRegistry, ElementSpace, LinearTriangle, Options, RegistryError};
/// let mut registry = ElementRegistry::builtin();
/// assert_eq!(registry.names(), ["vem1", "vem1-shear", "vem1-drecipe", "vem1-bbar", "p1"]);
/// assert_eq!(registry.make(ElementRegistry::DEFAULT)?.name(), "vem1");
/// // A stabilisation by its settings.
/// let shear = Options::new().with(
///     "stabilisation",
///     serde_json::json!({ "name": "dofi-dofi", "scaling": "shear" }),
/// );
/// assert_eq!(registry.make_with("vem1", &shear)?.name(), "vem1-shear");
/// registry.register("my-p1", "the linear triangle again", || Arc::new(LinearTriangle))?;
/// assert_eq!(registry.make("my-p1")?.name(), "p1");
/// let unknown = registry.make("vem2").err().expect("no element is named vem2");
/// assert_eq!(
///     unknown.to_string(),
///     "unknown element 'vem2' (known: vem1, vem1-shear, vem1-drecipe, vem1-bbar, p1, my-p1)"
/// );
/// # Ok::<(), RegistryError>(())
/// ```
#[derive(Clone, Debug)]
pub struct ElementRegistry {
    elements: Registry<Arc<dyn ElementSpace>, StabilisationRegistry>,
    stabilisations: StabilisationRegistry,
    polyhedral: Registry<Arc<dyn PolyhedralElement>, PolyhedralStabilisationRegistry>,
    polyhedral_stabilisations: PolyhedralStabilisationRegistry,
}

impl Default for ElementRegistry {
    /// The built-in elements, as [`ElementRegistry::builtin`].
    fn default() -> Self {
        Self::builtin()
    }
}

/// The settings of the lowest-order VEM.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct VemSettings {
    #[serde(default)]
    stabilisation: Option<Choice>,
}

impl ElementRegistry {
    /// The name of the default element: the lowest-order VEM, dofi-dofi scaled by `trace(C)`.
    pub const DEFAULT: &'static str = "vem1";

    /// A registry without any element, with the built-in stabilisations.
    pub fn empty() -> Self {
        Self {
            elements: Registry::empty("element"),
            stabilisations: StabilisationRegistry::builtin_stabilisations(),
            polyhedral: Registry::empty("element in 3D"),
            polyhedral_stabilisations:
                PolyhedralStabilisationRegistry::builtin_polyhedral_stabilisations(),
        }
    }

    /// The elements of this crate: `"vem1"` (default; its `stabilisation` setting names one of
    /// [`ElementRegistry::stabilisations`], dofi-dofi with `trace(C)` by default),
    /// `"vem1-shear"` (dofi-dofi, shear modulus), `"vem1-drecipe"` (D-recipe), `"vem1-bbar"`
    /// (locking-free: [`BBar`]) and `"p1"` (linear triangle, triangles only). Each element's
    /// [`ElementSpace::name`] is its registry name.
    pub fn builtin() -> Self {
        let mut registry = Self::empty();
        let fixed = |stabilisation: Arc<dyn Stabilisation>, what: &'static str| {
            move |o: &Options, _: &StabilisationRegistry| {
                o.refuse_all(what)?;
                Ok(
                    Arc::new(LowestOrderVem::from_valid(Arc::clone(&stabilisation)))
                        as Arc<dyn ElementSpace>,
                )
            }
        };
        let elements = &mut registry.elements;
        elements
            .register_with(
                "vem1",
                "lowest-order VEM, any polygon; stabilisation by setting (default dofi-dofi, alpha = trace(C)/8)",
                |o: &Options, stabilisations: &StabilisationRegistry| {
                    let settings: VemSettings = o.parse()?;
                    let stabilisation = match settings.stabilisation {
                        None => Arc::new(DofiDofi::default()) as Arc<dyn Stabilisation>,
                        Some(choice) => stabilisations.make_choice(&choice).map_err(|e| {
                            let path = match e.option_path() {
                                Some("") | None => "stabilisation".to_string(),
                                Some(p) => format!("stabilisation.{p}"),
                            };
                            OptionsError::at(path, e.to_string())
                        })?,
                    };
                    Ok(Arc::new(LowestOrderVem::from_valid(stabilisation)) as Arc<dyn ElementSpace>)
                },
            )
            .and_then(|r| {
                r.register_with(
                    "vem1-shear",
                    "lowest-order VEM, any polygon; dofi-dofi stabilisation alpha = 5 mu/8",
                    fixed(
                        Arc::new(DofiDofi::new(StabilisationScaling::ShearModulus)),
                        "vem1-shear",
                    ),
                )
            })
            .and_then(|r| {
                r.register_with(
                    "vem1-drecipe",
                    "lowest-order VEM, any polygon; D-recipe stabilisation S = diag(K_c)",
                    fixed(Arc::new(DRecipe), "vem1-drecipe"),
                )
            })
            .and_then(|r| {
                r.register_with(
                    "vem1-bbar",
                    "lowest-order VEM, any polygon; locking-free: alpha = min(trace(C), 3 trace(C_dev))/8",
                    fixed(Arc::new(BBar), "vem1-bbar"),
                )
            })
            .and_then(|r| {
                r.register_with(
                    "p1",
                    "linear triangle (P1 finite element), triangles only",
                    |o: &Options, _: &StabilisationRegistry| {
                        o.refuse_all("p1")?;
                        Ok(Arc::new(LinearTriangle) as Arc<dyn ElementSpace>)
                    },
                )
            })
            .expect("built-in names are valid and distinct");
        registry.register_builtin_polyhedral();
        registry
    }

    /// The elements on polyhedra, under the names of their planar counterparts: `"vem1"`
    /// ([`PolyhedralVem`], setting `stabilisation` as in 2D), `"vem1-shear"`, `"vem1-drecipe"`,
    /// `"vem1-bbar"` and `"p1"` ([`LinearTetrahedron`], tetrahedra only).
    fn register_builtin_polyhedral(&mut self) {
        let fixed = |stabilisation: Arc<dyn PolyhedralStabilisation>, what: &'static str| {
            move |o: &Options, _: &PolyhedralStabilisationRegistry| {
                o.refuse_all(what)?;
                let element = PolyhedralVem::try_new(Arc::clone(&stabilisation))
                    .map_err(|e| OptionsError::at("", e.to_string()))?;
                Ok(Arc::new(element) as Arc<dyn PolyhedralElement>)
            }
        };
        self.polyhedral
            .register_with(
                "vem1",
                "lowest-order VEM, any polyhedron; stabilisation by setting (default dofi-dofi, alpha = trace(C) l_E/48)",
                |o: &Options, stabilisations: &PolyhedralStabilisationRegistry| {
                    let settings: VemSettings = o.parse()?;
                    let stabilisation = match settings.stabilisation {
                        None => Arc::new(DofiDofi::default()) as Arc<dyn PolyhedralStabilisation>,
                        Some(choice) => stabilisations.make_choice(&choice).map_err(|e| {
                            let path = match e.option_path() {
                                Some("") | None => "stabilisation".to_string(),
                                Some(p) => format!("stabilisation.{p}"),
                            };
                            OptionsError::at(path, e.to_string())
                        })?,
                    };
                    let element = PolyhedralVem::try_new(stabilisation)
                        .map_err(|e| OptionsError::at("stabilisation", e.to_string()))?;
                    Ok(Arc::new(element) as Arc<dyn PolyhedralElement>)
                },
            )
            .and_then(|r| {
                r.register_with(
                    "vem1-shear",
                    "lowest-order VEM, any polyhedron; dofi-dofi stabilisation alpha = 9 mu l_E/48",
                    fixed(
                        Arc::new(DofiDofi::new(StabilisationScaling::ShearModulus)),
                        "vem1-shear",
                    ),
                )
            })
            .and_then(|r| {
                r.register_with(
                    "vem1-drecipe",
                    "lowest-order VEM, any polyhedron; D-recipe stabilisation S = diag(K_c)",
                    fixed(Arc::new(DRecipe), "vem1-drecipe"),
                )
            })
            .and_then(|r| {
                r.register_with(
                    "vem1-bbar",
                    "lowest-order VEM, any polyhedron; locking-free: alpha = min(trace(C), 3 trace(C_dev)) l_E/48",
                    fixed(Arc::new(BBar), "vem1-bbar"),
                )
            })
            .and_then(|r| {
                r.register_with(
                    "p1",
                    "linear tetrahedron (P1 finite element), tetrahedra only",
                    |o: &Options, _: &PolyhedralStabilisationRegistry| {
                        o.refuse_all("p1")?;
                        Ok(Arc::new(LinearTetrahedron) as Arc<dyn PolyhedralElement>)
                    },
                )
            })
            .expect("built-in names are valid and distinct");
    }

    /// The names of the elements on polyhedra, in registration order.
    pub fn polyhedral_names(&self) -> Vec<&str> {
        self.polyhedral.names()
    }

    /// The one-line summary of the element on polyhedra `name`, if registered.
    pub fn polyhedral_summary(&self, name: &str) -> Option<&str> {
        self.polyhedral.summary(name)
    }

    /// The element on polyhedra of a [`Choice`]; an unknown name lists the known ones.
    ///
    /// ```
    /// use vem_space::{Choice, ElementRegistry, Options};
    /// let registry = ElementRegistry::builtin();
    /// assert_eq!(registry.polyhedral_names(), ["vem1", "vem1-shear", "vem1-drecipe", "vem1-bbar", "p1"]);
    /// let drecipe = Choice::with_options(
    ///     "vem1",
    ///     Options::new().with("stabilisation", "drecipe"),
    /// );
    /// assert_eq!(registry.make_polyhedral_choice(&drecipe)?.name(), "vem1-drecipe");
    /// # Ok::<(), vem_space::RegistryError>(())
    /// ```
    ///
    /// # Errors
    /// [`RegistryError::UnknownName`] listing the known names, [`RegistryError::Options`]
    /// naming the refused setting.
    pub fn make_polyhedral_choice(
        &self,
        choice: &Choice,
    ) -> Result<Arc<dyn PolyhedralElement>, RegistryError> {
        self.polyhedral.make_in(
            &choice.name,
            &choice.options,
            &self.polyhedral_stabilisations,
        )
    }

    /// Adds the element on polyhedra `name` built from its settings by `factory` (which may
    /// look up the stabilisations on polyhedra by name).
    ///
    /// # Errors
    /// As [`ElementRegistry::register`].
    pub fn register_polyhedral(
        &mut self,
        name: impl Into<String>,
        summary: impl Into<String>,
        factory: impl Fn(
                &Options,
                &PolyhedralStabilisationRegistry,
            ) -> Result<Arc<dyn PolyhedralElement>, OptionsError>
            + Send
            + Sync
            + 'static,
    ) -> Result<&mut Self, RegistryError> {
        self.polyhedral.register_with(name, summary, factory)?;
        Ok(self)
    }

    /// Adds the element `name` with a one-line `summary`, built by `factory` (it takes no
    /// settings). The name must be new, non-empty and made of ASCII letters, digits, `-` and
    /// `_`.
    ///
    /// # Errors
    /// [`RegistryError::InvalidName`], [`RegistryError::DuplicateName`].
    pub fn register(
        &mut self,
        name: impl Into<String>,
        summary: impl Into<String>,
        factory: impl Fn() -> Arc<dyn ElementSpace> + Send + Sync + 'static,
    ) -> Result<&mut Self, RegistryError> {
        let name = name.into();
        let what = name.clone();
        self.elements.register_with(
            name,
            summary,
            move |o: &Options, _: &StabilisationRegistry| {
                o.refuse_all(&what)?;
                Ok(factory())
            },
        )?;
        Ok(self)
    }

    /// Adds the element `name` built from its settings by `factory` (which may look up
    /// stabilisations by name).
    ///
    /// # Errors
    /// As [`ElementRegistry::register`].
    pub fn register_with_options(
        &mut self,
        name: impl Into<String>,
        summary: impl Into<String>,
        factory: impl Fn(&Options, &StabilisationRegistry) -> Result<Arc<dyn ElementSpace>, OptionsError>
            + Send
            + Sync
            + 'static,
    ) -> Result<&mut Self, RegistryError> {
        self.elements.register_with(name, summary, factory)?;
        Ok(self)
    }

    /// The stabilisations the lowest-order VEM may name; a user's own joins with
    /// [`Registry::register`].
    pub fn stabilisations(&self) -> &StabilisationRegistry {
        &self.stabilisations
    }

    /// The stabilisations, to register one's own.
    pub fn stabilisations_mut(&mut self) -> &mut StabilisationRegistry {
        &mut self.stabilisations
    }

    /// The registered names, in registration order.
    pub fn names(&self) -> Vec<&str> {
        self.elements.names()
    }

    /// Whether `name` is registered.
    pub fn contains(&self, name: &str) -> bool {
        self.elements.contains(name)
    }

    /// The one-line summary of `name`, if registered.
    pub fn summary(&self, name: &str) -> Option<&str> {
        self.elements.summary(name)
    }

    /// A new element of the type `name` with its default settings; an unknown name is an error
    /// that lists the known ones.
    ///
    /// # Errors
    /// As [`ElementRegistry::make_with`].
    pub fn make(&self, name: &str) -> Result<Arc<dyn ElementSpace>, RegistryError> {
        self.make_with(name, &Options::new())
    }

    /// A new element of the type `name` with the settings `options`.
    ///
    /// # Errors
    /// [`RegistryError::UnknownName`] listing the known names, [`RegistryError::Options`]
    /// naming the refused setting.
    pub fn make_with(
        &self,
        name: &str,
        options: &Options,
    ) -> Result<Arc<dyn ElementSpace>, RegistryError> {
        self.elements.make_in(name, options, &self.stabilisations)
    }

    /// The element of a [`Choice`].
    ///
    /// # Errors
    /// As [`ElementRegistry::make_with`].
    pub fn make_choice(&self, choice: &Choice) -> Result<Arc<dyn ElementSpace>, RegistryError> {
        self.make_with(&choice.name, &choice.options)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn builtin_names_are_the_element_names() {
        let registry = ElementRegistry::builtin();
        for name in registry.names() {
            assert_eq!(registry.make(name).unwrap().name(), name);
            assert!(!registry.summary(name).unwrap().is_empty());
        }
        // The same names on polyhedra, each element named as registered.
        assert_eq!(registry.polyhedral_names(), registry.names());
        for name in registry.polyhedral_names() {
            let element = registry
                .make_polyhedral_choice(&Choice::named(name))
                .unwrap();
            assert_eq!(element.name(), name);
            assert!(!registry.polyhedral_summary(name).unwrap().is_empty());
        }
        let shear = Choice::with_options(
            "vem1",
            Options::new().with(
                "stabilisation",
                serde_json::json!({ "name": "dofi-dofi", "scaling": "shear" }),
            ),
        );
        assert_eq!(
            registry.make_polyhedral_choice(&shear).unwrap().name(),
            "vem1-shear"
        );
        let bad = Choice::with_options(
            "vem1",
            Options::new().with(
                "stabilisation",
                serde_json::json!({ "name": "dofi-dofi", "scale": -1.0 }),
            ),
        );
        let error = registry.make_polyhedral_choice(&bad).err().unwrap();
        assert_eq!(error.option_path(), Some("stabilisation.scale"));
        assert!(registry.contains(ElementRegistry::DEFAULT));
    }

    #[test]
    fn settings_are_checked_with_their_path() {
        let registry = ElementRegistry::builtin();
        let bad_scale = Options::new().with(
            "stabilisation",
            serde_json::json!({ "name": "dofi-dofi", "scale": -1.0 }),
        );
        let err = registry.make_with("vem1", &bad_scale).err().unwrap();
        assert_eq!(err.option_path(), Some("stabilisation.scale"), "{err}");
        let unknown = Options::new().with("stabilisation", "dofi");
        let err = registry.make_with("vem1", &unknown).err().unwrap();
        assert!(
            err.to_string().contains("unknown stabilisation 'dofi'"),
            "{err}"
        );
        let refused = Options::new().with("scale", 2.0);
        let err = registry.make_with("p1", &refused).err().unwrap();
        assert_eq!(err.option_path(), Some("scale"));
        let drecipe = Options::new().with("stabilisation", "drecipe");
        assert_eq!(
            registry.make_with("vem1", &drecipe).unwrap().name(),
            "vem1-drecipe"
        );
    }

    #[test]
    fn duplicate_and_invalid_names_are_errors() {
        let mut registry = ElementRegistry::builtin();
        let err = registry
            .register("p1", "again", || Arc::new(LinearTriangle))
            .unwrap_err();
        assert_eq!(
            err,
            RegistryError::DuplicateName {
                kind: "element",
                name: "p1".into()
            }
        );
        for bad in ["", "with space", "é"] {
            assert!(matches!(
                registry.register(bad, "", || Arc::new(LinearTriangle)),
                Err(RegistryError::InvalidName { .. })
            ));
        }
        assert_eq!(registry.names().len(), 5);
        assert_eq!(registry.summary("nothing"), None);
    }
}
