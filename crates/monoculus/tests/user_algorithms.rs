//! Algorithms written outside the workspace's core, as a user writes them: their
//! parameters are read strictly from `[algorithm.params]` and swept like any key, and a
//! bad decision or a panic fails that run only, recorded with the algorithm, the robot
//! and the round, while the other runs of the sweep go on.

use std::path::Path;

use monoculus::prelude::*;
use monoculus::{Experiment, Registry};
use monoculus_experiments::run_experiment;

/// Turns the direction of a random visible robot by `angle` (radians, in the plane).
struct Turn {
    angle: f64,
}

#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct TurnParams {
    angle: f64,
}

impl Algorithm for Turn {
    const NAME: &'static str = "turn";
    type Sensing = Directions;
    type Params = TurnParams;
    type State = ();
    const STOP: StopCriterion = StopCriterion::Diameter;
    const PLANE_ONLY: Option<&'static str> = Some("turns in the plane");

    fn new(p: TurnParams) -> Result<Self, String> {
        if p.angle.is_nan() || p.angle.abs() > std::f64::consts::PI {
            return Err(format!("angle = {}: at most pi in magnitude", p.angle));
        }
        Ok(Turn { angle: p.angle })
    }

    fn decide<V: Point>(
        &self,
        obs: &Observation<'_, Directions, V>,
        _: &mut (),
        rng: &mut Stream,
    ) -> Decision<V> {
        let Some(d) = obs.random_visible(rng) else {
            return Decision::Stay;
        };
        let (c, s) = (self.angle.cos(), self.angle.sin());
        let (x, y) = (d.axis(0), d.axis(1));
        Decision::Step(V::from_slice(&[c * x - s * y, s * x + c * y]))
    }
}

/// Moves toward the sole visible point or a random far one, but with probability `p` an
/// activation goes wrong: a step twice too long, or a panic.
struct Flaky {
    p: f64,
    panics: bool,
}

#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
struct FlakyParams {
    p: f64,
    #[serde(default)]
    panics: bool,
}

impl Algorithm for Flaky {
    const NAME: &'static str = "flaky";
    type Sensing = Ld;
    type Params = FlakyParams;
    type State = ();

    fn new(p: FlakyParams) -> Result<Self, String> {
        Ok(Flaky {
            p: p.p,
            panics: p.panics,
        })
    }

    fn decide<V: Point>(
        &self,
        obs: &Observation<'_, Ld, V>,
        _: &mut (),
        rng: &mut Stream,
    ) -> Decision<V> {
        let toward = obs.sole_visible().or_else(|| obs.random_far(rng));
        match toward {
            Some(d) if rng.uniform() < self.p => {
                if self.panics {
                    panic!("flaky gave up");
                }
                Decision::Step(d * 2.0)
            }
            Some(d) => Decision::Step(d),
            None => Decision::Stay,
        }
    }
}

fn registry() -> Registry {
    let mut r = Registry::builtin();
    r.register::<Turn>().register::<Flaky>();
    r
}

fn parse(text: &str) -> Result<Experiment, String> {
    Experiment::parse(text, "user.toml", Path::new("."), &[], &registry())
        .map_err(|e| e.to_string())
}

const TURN: &str = r#"name = "turning"
seeds = 3

[swarm]
n = 12
init = "square"
side = 6.0

[algorithm]
name = "turn"

[algorithm.params]
angle = [0.0, 0.3]

[stop]
max_rounds = 200
"#;

#[test]
fn params_sweep_with_a_column_and_a_place_in_the_cell_label() {
    let exp = parse(TURN).unwrap();
    let keys: Vec<&str> = exp.cells.iter().map(|c| c.key.as_str()).collect();
    assert_eq!(
        keys,
        ["algorithm.params.angle=0.0", "algorithm.params.angle=0.3"]
    );
    let tmp = tempfile::tempdir().unwrap();
    let report = run_experiment(&exp, tmp.path(), Default::default(), &()).unwrap();
    assert!(report.failed.is_empty());
    let runs = std::fs::read_to_string(tmp.path().join("runs.csv")).unwrap();
    let header: Vec<&str> = runs.lines().next().unwrap().split(',').collect();
    let col = header
        .iter()
        .position(|h| *h == "algorithm.params.angle")
        .unwrap();
    let values: Vec<&str> = runs
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(col).unwrap())
        .collect();
    assert_eq!(values, ["0.0", "0.0", "0.0", "0.3", "0.3", "0.3"]);
    // The resolved config holds the parameters in full.
    assert!(
        exp.resolved.contains("[algorithm.params]"),
        "{}",
        exp.resolved
    );
}

#[test]
fn bad_params_name_their_key_and_line() {
    let cases = [
        (
            TURN.replace("angle = [0.0, 0.3]", "angle = \"wide\""),
            "user.toml:13: algorithm.params.angle: invalid type",
        ),
        (
            TURN.replace("angle = [0.0, 0.3]", "angle = 0.1\nspin = 2"),
            "user.toml:14: algorithm.params.spin: unknown field `spin`, expected `angle`",
        ),
        (
            TURN.replace("angle = [0.0, 0.3]", "angle = 9.0"),
            "user.toml:12: algorithm.params: angle = 9: at most pi in magnitude",
        ),
        (
            TURN.replace("angle = [0.0, 0.3]", ""),
            "algorithm.params.angle: missing field `angle`",
        ),
        (
            TURN.replace("n = 12", "n = 12\ndim = 3"),
            "algorithm.name: turn turns in the plane: dim must be 2",
        ),
        (
            TURN.replace("name = \"turn\"", "name = \"spin\""),
            "user.toml:10: algorithm.name: `spin` is not a registered algorithm; registered are converge_locality, converge_quadrant, converge_quadrant_termination, center_of_gravity, median, angle_bisector, turn, flaky",
        ),
    ];
    for (text, want) in cases {
        let e = parse(&text).unwrap_err();
        assert!(e.contains(want), "want {want:?}, got {e:?}");
    }
    // The struct forgot deny_unknown_fields: unknown keys are refused all the same.
    let flaky = TURN
        .replace("name = \"turn\"", "name = \"flaky\"")
        .replace("angle = [0.0, 0.3]", "p = 0.1\nangle = 1.0");
    assert!(
        parse(&flaky)
            .unwrap_err()
            .contains("algorithm.params.angle: flaky has no parameter")
    );
}

fn flaky(panics: bool) -> String {
    format!(
        "name = \"flaky\"\nseeds = 24\n[swarm]\nn = 6\ninit = \"square\"\nside = 8.0\n[algorithm]\nname = \"flaky\"\n[algorithm.params]\np = 0.01\npanics = {panics}\n[stop]\nmax_rounds = 30\n"
    )
}

#[test]
fn a_bad_step_or_a_panic_fails_that_run_and_the_sweep_goes_on() {
    for (panics, want) in [
        (false, "flaky: decided a step along"),
        (true, "flaky: panicked: flaky gave up"),
    ] {
        let exp = parse(&flaky(panics)).unwrap();
        let tmp = tempfile::tempdir().unwrap();
        let report = run_experiment(&exp, tmp.path(), Default::default(), &()).unwrap();
        let failed = report.failed.len();
        assert!((1..24).contains(&failed), "{failed} of 24 failed");
        assert_eq!(report.ran + failed, 24);
        let runs = std::fs::read_to_string(tmp.path().join("runs.csv")).unwrap();
        assert_eq!(runs.lines().count(), 1 + 24 - failed);
        let failures = std::fs::read_to_string(tmp.path().join("failures.csv")).unwrap();
        let lines: Vec<&str> = failures.lines().collect();
        assert_eq!(lines[0], "cell,seed,algorithm,robot,round,message");
        assert_eq!(lines.len(), 1 + failed);
        for l in &lines[1..] {
            assert!(l.contains(",flaky,") && l.contains(want), "{l}");
        }
        let (_, seed, message) = &report.failed[0];
        assert!(
            message.contains(want) && message.contains("(robot "),
            "{message}"
        );
        // Deterministic: the same runs fail, whatever the thread count.
        let again = tempfile::tempdir().unwrap();
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap();
        let one =
            pool.install(|| run_experiment(&exp, again.path(), Default::default(), &()).unwrap());
        assert_eq!(one.failed, report.failed, "seed {seed}");
    }
}
