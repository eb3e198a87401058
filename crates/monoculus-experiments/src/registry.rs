//! [`Registry`]: the algorithms a binary knows, by name, and how each reads its
//! parameters from a config's `[algorithm.params]`.

use monoculus_core::algorithms::{
    Algorithm, AngleBisector, CenterOfGravity, ConvergeLocality, ConvergeQuadrant,
    ConvergeQuadrantTermination, Median, Model, Sensing, StopCriterion,
};
use std::sync::Arc;

use monoculus_engine::AlgorithmBox;

/// Why `[algorithm.params]` does not make an algorithm: the key at fault (relative to
/// `algorithm.params`, empty for the table as a whole) and what is wrong.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ParamsError {
    /// The dotted key under `algorithm.params` (`angle`, `weights.near`), if one.
    pub key: String,
    /// What is wrong.
    pub message: String,
}

/// How an entry makes its algorithm from `[algorithm.params]`: the algorithm and its
/// parameters in full.
pub type Make =
    Arc<dyn Fn(&toml::Table) -> Result<(AlgorithmBox, toml::Table), ParamsError> + Send + Sync>;

/// One registered algorithm.
#[derive(Clone)]
pub struct Entry {
    name: String,
    model: Model,
    stop: StopCriterion,
    make: Make,
}

impl Entry {
    /// Its name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Its sensing model.
    pub fn model(&self) -> Model {
        self.model
    }

    /// Its default stop criterion.
    pub fn default_stop(&self) -> StopCriterion {
        self.stop
    }

    /// The algorithm with the parameters `params` (the config's `[algorithm.params]`,
    /// keys left out taking their defaults), and those parameters in full.
    pub fn make(&self, params: &toml::Table) -> Result<(AlgorithmBox, toml::Table), ParamsError> {
        (self.make)(params)
    }
}

/// The keys of `given` that `known` (its parameters as read and written back) lacks:
/// keys the algorithm's parameters do not have, whatever its struct says of unknown
/// fields.
fn unknown_key(given: &toml::Table, known: &toml::Table, prefix: &str) -> Option<String> {
    given.iter().find_map(|(k, v)| {
        let key = if prefix.is_empty() {
            k.clone()
        } else {
            format!("{prefix}.{k}")
        };
        match (v, known.get(k)) {
            (_, None) => Some(key),
            (toml::Value::Table(g), Some(toml::Value::Table(w))) => unknown_key(g, w, &key),
            _ => None,
        }
    })
}

/// `A` with the parameters `given` (`[algorithm.params]`), read strictly.
fn make<A: Algorithm>(given: &toml::Table) -> Result<(AlgorithmBox, toml::Table), ParamsError> {
    let params: A::Params = serde_path_to_error::deserialize(toml::Value::Table(given.clone()))
        .map_err(|e| {
            let key = e.path().to_string();
            let message = e.inner().message().to_string();
            // serde names an unknown or missing field in its message; the key is it.
            let field = ["unknown field `", "missing field `"]
                .iter()
                .find_map(|m| message.split(m).nth(1)?.split('`').next());
            let key = match (key.as_str(), field) {
                (".", Some(f)) => f.to_string(),
                (".", None) => String::new(),
                (k, Some(f)) if !k.ends_with(f) => format!("{k}.{f}"),
                (k, _) => k.to_string(),
            };
            ParamsError {
                key,
                message: message.replace(", expected one of", "; expected one of"),
            }
        })?;
    let resolved = toml::Table::try_from(&params).map_err(|e| ParamsError {
        key: String::new(),
        message: format!(
            "{}'s parameters cannot be written back as a table: {e}",
            A::NAME
        ),
    })?;
    if let Some(key) = unknown_key(given, &resolved, "") {
        return Err(ParamsError {
            key,
            message: format!("{} has no parameter of that name", A::NAME),
        });
    }
    let algorithm = A::new(params).map_err(|message| ParamsError {
        key: String::new(),
        message,
    })?;
    Ok((AlgorithmBox::new(algorithm), resolved))
}

/// The algorithms a binary knows, by name: what a config's `algorithm.name` selects.
/// [`Registry::builtin`] holds the paper's six; a user's binary adds its own with
/// [`Registry::register`] (the `monoculus` crate's `App` does it for a `main`).
///
/// ```
/// use monoculus_experiments::Registry;
///
/// let registry = Registry::builtin();
/// assert!(registry.get("converge_locality").is_some());
/// assert_eq!(registry.names().len(), 6);
/// ```
#[derive(Clone, Default)]
pub struct Registry {
    entries: Vec<Entry>,
}

impl Registry {
    /// No algorithm at all.
    pub fn new() -> Self {
        Registry::default()
    }

    /// The paper's algorithms: converge_locality, converge_quadrant,
    /// converge_quadrant_termination, center_of_gravity, median, angle_bisector.
    pub fn builtin() -> Self {
        let mut r = Registry::new();
        r.register::<ConvergeLocality>()
            .register::<ConvergeQuadrant>()
            .register::<ConvergeQuadrantTermination>()
            .register::<CenterOfGravity>()
            .register::<Median>()
            .register::<AngleBisector>();
        r
    }

    /// Adds `A`, by [`Algorithm::NAME`]. A name registered twice is a mistake of the
    /// binary's author, found when it starts: it panics, naming it (see
    /// [`Registry::try_register`]).
    pub fn register<A: Algorithm>(&mut self) -> &mut Self {
        if let Err(e) = self.try_register::<A>() {
            panic!("{e}");
        }
        self
    }

    /// Adds `A`, or says why not (its name is taken, or not a plain snake-case name, or
    /// it declares more than [`MAX_LIGHTS`](monoculus_core::algorithms::MAX_LIGHTS)
    /// lights).
    pub fn try_register<A: Algorithm>(&mut self) -> Result<&mut Self, String> {
        let max = monoculus_core::algorithms::MAX_LIGHTS;
        if A::LIGHTS.len() > max {
            return Err(format!(
                "algorithm {:?} declares {} lights: at most {max}",
                A::NAME,
                A::LIGHTS.len()
            ));
        }
        self.try_register_with(
            A::NAME,
            <A::Sensing as Sensing>::MODEL,
            A::STOP,
            Arc::new(make::<A>),
        )
    }

    /// Adds an algorithm named at run time (bindings to other languages, whose
    /// algorithms are values of one Rust type): its name, model, default stop criterion
    /// and how it is made from `[algorithm.params]`.
    pub fn try_register_with(
        &mut self,
        name: &str,
        model: Model,
        stop: StopCriterion,
        make: Make,
    ) -> Result<&mut Self, String> {
        if name.is_empty()
            || !name
                .chars()
                .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_')
        {
            return Err(format!(
                "algorithm name {name:?}: use lower-case letters, digits and _"
            ));
        }
        if self.get(name).is_some() {
            return Err(format!(
                "two algorithms are registered as {name:?}: names must be unique"
            ));
        }
        self.entries.push(Entry {
            name: name.to_string(),
            model,
            stop,
            make,
        });
        Ok(self)
    }

    /// The algorithm registered as `name`.
    pub fn get(&self, name: &str) -> Option<&Entry> {
        self.entries.iter().find(|e| e.name == name)
    }

    /// Every registered name, in the order registered.
    pub fn names(&self) -> Vec<&str> {
        self.entries.iter().map(|e| e.name.as_str()).collect()
    }
}

impl std::fmt::Debug for Registry {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_list().entries(self.names()).finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use monoculus_core::algorithms::{Decision, Observation};
    use monoculus_core::geometry::Point;
    use monoculus_core::rng::Stream;

    #[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
    struct Turn {
        angle: f64,
        #[serde(default)]
        weights: Weights,
    }

    #[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
    struct Weights {
        near: f64,
    }

    struct Turning(Turn);

    impl Algorithm for Turning {
        const NAME: &'static str = "turning";
        type Sensing = monoculus_core::algorithms::Directions;
        type Params = Turn;
        type State = ();
        fn new(p: Turn) -> Result<Self, String> {
            if p.angle.abs() > 3.2 {
                return Err(format!("angle = {}: at most pi", p.angle));
            }
            Ok(Turning(p))
        }
        fn decide<V: Point>(
            &self,
            _: &Observation<'_, Self::Sensing, V>,
            _: &mut (),
            _: &mut Stream,
        ) -> Decision<V> {
            let _ = self.0.angle;
            Decision::Stay
        }
    }

    fn table(text: &str) -> toml::Table {
        toml::from_str(text).unwrap()
    }

    #[test]
    fn params_are_read_strictly_and_errors_name_their_key() {
        let mut r = Registry::new();
        r.register::<Turning>();
        let e = r.get("turning").unwrap();
        let (_, resolved) = e.make(&table("angle = 1.5")).unwrap();
        assert_eq!(resolved, table("angle = 1.5\n[weights]\nnear = 0.0"));
        let err = |t: &str| e.make(&table(t)).err().unwrap();
        assert_eq!(err("angle = \"x\"").key, "angle");
        assert_eq!(err("angle = 1.0\nspin = 2").key, "spin");
        assert_eq!(
            err("angle = 1.0\nweights = { near = 1.0, far = 2.0 }").key,
            "weights.far"
        );
        assert_eq!(err("").key, "angle");
        assert_eq!(err("angle = 9.0").message, "angle = 9: at most pi");
        assert!(r.try_register::<Turning>().is_err());
    }
}
