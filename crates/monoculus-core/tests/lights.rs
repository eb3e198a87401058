//! Lights (the luminous-robot model): what a robot sees of the others' colours, the
//! random choice among a colour's robots, and a colour out of the palette.

use glam::DVec2;
use monoculus_core::algorithms::{
    Algorithm, Decision, Directions, Kept, LocalFrame, ModelParams, NoParams, Observation,
    activate, activate_lit,
};
use monoculus_core::geometry::Point;
use monoculus_core::rng::Stream;
use monoculus_core::vision::{ExactSight, VisionParams};

/// What a robot saw in its last activation, and the colour it shows.
#[derive(Clone, Debug, Default, PartialEq)]
struct Saw {
    light: usize,
    colours: Vec<usize>,
    directions: usize,
    sees: [bool; 3],
}

/// Records the colours it sees, turns its light to `on`, and steps toward a random
/// robot showing `blink`.
struct Recorder;

impl Algorithm for Recorder {
    const NAME: &'static str = "recorder";
    type Sensing = Directions;
    type Params = NoParams;
    type State = Saw;
    const LIGHTS: &'static [&'static str] = &["off", "on", "blink"];

    fn new(_: NoParams) -> Result<Self, String> {
        Ok(Recorder)
    }

    fn light(state: &Saw) -> usize {
        state.light
    }

    fn decide<V: Point>(
        &self,
        obs: &Observation<'_, Directions, V>,
        state: &mut Saw,
        rng: &mut Stream,
    ) -> Decision<V> {
        let lit = obs.lit();
        // Listed in the order of the directions.
        let directions = obs.directions();
        assert_eq!(lit.len(), directions.len());
        for (l, d) in lit.iter().zip(&directions) {
            assert!((l.direction - *d).length() < 1e-12);
        }
        let mut colours: Vec<usize> = lit.iter().map(|l| l.light).collect();
        colours.sort_unstable();
        *state = Saw {
            light: 1,
            colours,
            directions: directions.len(),
            sees: [0, 1, 2].map(|l| obs.sees_light(l)),
        };
        obs.random_lit(2, rng)
            .map_or(Decision::Stay, Decision::Step)
    }
}

/// Shows a colour it does not declare.
struct OutOfPalette;

impl Algorithm for OutOfPalette {
    const NAME: &'static str = "out_of_palette";
    type Sensing = Directions;
    type Params = NoParams;
    type State = usize;
    const LIGHTS: &'static [&'static str] = &["off", "on"];

    fn new(_: NoParams) -> Result<Self, String> {
        Ok(OutOfPalette)
    }

    fn light(state: &usize) -> usize {
        *state
    }

    fn decide<V: Point>(
        &self,
        _: &Observation<'_, Directions, V>,
        state: &mut usize,
        _: &mut Stream,
    ) -> Decision<V> {
        *state = 5;
        Decision::Stay
    }
}

/// Robot 0 at the origin; robot 1 on +x shows blink; robot 2 behind it shows on; robots
/// 3 and 4 share a point on +y, showing off and blink.
fn swarm() -> ExactSight<DVec2> {
    let pts = [(0.0, 0.0), (1.0, 0.0), (2.0, 0.0), (0.0, 1.0), (0.0, 1.0)];
    ExactSight::new(
        pts.iter().map(|&(x, y)| DVec2::new(x, y)).collect(),
        VisionParams::default(),
    )
}

const LIGHTS: [u8; 5] = [0, 2, 1, 0, 2];

fn kept<T: Default>(seed: u64) -> Kept<DVec2, T> {
    let mut stream = Stream::new(seed, 1, 0, 0);
    Kept {
        frame: LocalFrame::draw(monoculus_core::algorithms::Model::Directions, &mut stream),
        state: T::default(),
    }
}

#[test]
fn a_robot_sees_the_colour_of_each_visible_point_and_not_of_hidden_robots() {
    let sight = swarm();
    let params = ModelParams::new(1.0, 2.0);
    for seed in 0..20 {
        let mut memory = kept::<Saw>(seed);
        let mut stream = Stream::new(seed, 2, 0, 0);
        let step = activate_lit(
            &Recorder,
            &params,
            (&sight, &LIGHTS),
            0,
            Some(&mut memory),
            &mut stream,
        )
        .unwrap();
        // Robot 2 is hidden behind robot 1; robots 3 and 4 are one point, showing the
        // colour of robot 3 (the lowest index).
        assert_eq!(memory.state.colours, vec![0, 2]);
        assert_eq!(memory.state.directions, 2);
        assert_eq!(
            memory.state.sees,
            [true, false, true],
            "robot 2 shows on, hidden"
        );
        assert_eq!(memory.state.light, 1);
        // The only visible robot showing blink is robot 1, along +x, whatever the frame.
        let step = step.expect("a robot shows blink");
        assert!((step - DVec2::X).length() < 1e-9, "{step:?}");
    }
}

#[test]
fn random_lit_is_uniform_over_the_visible_points_of_its_colour() {
    // Robot 0 in the middle of a ring of 12, every third robot showing blink.
    let mut pts = vec![DVec2::ZERO];
    let mut lights = vec![0u8];
    for k in 0..12 {
        let a = k as f64 * std::f64::consts::TAU / 12.0;
        pts.push(DVec2::new(a.cos(), a.sin()) * 3.0);
        lights.push(if k % 3 == 0 { 2 } else { 1 });
    }
    let sight = ExactSight::new(pts.clone(), VisionParams::default());
    let params = ModelParams::new(1.0, 2.0);
    let mut counts = [0usize; 12];
    for seed in 0..4000 {
        let mut memory = kept::<Saw>(seed);
        let mut stream = Stream::new(seed, 3, 0, 0);
        let step = activate_lit(
            &Recorder,
            &params,
            (&sight, &lights),
            0,
            Some(&mut memory),
            &mut stream,
        )
        .unwrap()
        .expect("four robots show blink");
        let k = (1..13)
            .find(|&j| (pts[j].normalize() - step).length() < 1e-9)
            .expect("a step toward a robot of the ring");
        counts[k - 1] += 1;
    }
    for (k, &c) in counts.iter().enumerate() {
        if k % 3 == 0 {
            // 1000 expected each; 5 standard deviations is about 140.
            assert!((860..=1140).contains(&c), "robot {}: {c}", k + 1);
        } else {
            assert_eq!(c, 0, "robot {} shows on, not blink", k + 1);
        }
    }
}

#[test]
fn without_lights_every_robot_shows_the_first_colour() {
    let sight = swarm();
    let params = ModelParams::new(1.0, 2.0);
    let mut memory = kept::<Saw>(1);
    let step = activate(
        &Recorder,
        &params,
        &sight,
        0,
        Some(&mut memory),
        &mut Stream::new(1, 2, 0, 0),
    )
    .unwrap();
    assert_eq!(memory.state.colours, vec![0, 0]);
    assert_eq!(memory.state.sees, [true, false, false]);
    assert_eq!(step, None, "nobody shows blink");
}

#[test]
fn a_colour_out_of_the_palette_is_a_bad_decision_naming_the_algorithm() {
    let sight = swarm();
    let params = ModelParams::new(1.0, 2.0);
    let mut memory = kept::<usize>(1);
    let bad = activate_lit(
        &OutOfPalette,
        &params,
        (&sight, &LIGHTS),
        0,
        Some(&mut memory),
        &mut Stream::new(1, 2, 0, 0),
    )
    .unwrap_err();
    assert_eq!(bad.algorithm, "out_of_palette");
    assert!(bad.problem.contains("shows light 5"), "{}", bad.problem);
    assert!(bad.problem.contains("2 lights"), "{}", bad.problem);
}
