use std::path::PathBuf;

use glam::DVec2;
use monoculus_core::impossibility::{construction, directions, leaves_hull};
use monoculus_experiments::results::num;

use super::Failure;

#[derive(clap::Args, Debug)]
pub struct ImpossibilityArgs {
    /// Directions from robot 0 to the others, in degrees.
    #[arg(long, value_delimiter = ',', default_value = "20,50,80")]
    angles: Vec<f64>,
    /// The others' distance from robot 0 in the near configuration.
    #[arg(long, default_value_t = 0.2)]
    near: f64,
    /// Their distance in the far configuration.
    #[arg(long, default_value_t = 6.0)]
    far: f64,
    /// Step length b.
    #[arg(long, default_value_t = 1.0)]
    step: f64,
    /// Locality constant c (the far bit of Locality Detection).
    #[arg(long, default_value_t = 2.0)]
    locality: f64,
    /// Move directions tested, evenly spaced.
    #[arg(long, default_value_t = 360)]
    moves: usize,
    /// Folder for the figure (impossibility.png and .svg); none without it.
    #[arg(long)]
    out: Option<PathBuf>,
}

/// The impossibility construction: prints, for robot 0's moves in evenly spaced
/// directions, whether each leaves the hull of the near and of the far configuration,
/// and whether every one leaves at least one (model.md, "Why directions alone are not
/// enough").
pub fn impossibility(args: ImpossibilityArgs) -> Result<(), Failure> {
    for (name, x) in [
        ("--near", args.near),
        ("--far", args.far),
        ("--step", args.step),
        ("--locality", args.locality),
    ] {
        if !(x > 0.0 && x.is_finite()) {
            return Err(Failure::Input(format!("{name} {x}: must be positive")));
        }
    }
    if args.angles.is_empty() || args.angles.iter().any(|a| !a.is_finite()) {
        return Err(Failure::Input(
            "--angles: give finite angles in degrees, e.g. 20,50,80".into(),
        ));
    }
    if args.moves == 0 || args.moves > 100_000 {
        return Err(Failure::Input(format!(
            "--moves {}: between 1 and 100000",
            args.moves
        )));
    }
    let radians: Vec<f64> = args.angles.iter().map(|a| a.to_radians()).collect();
    let c = construction(&radians, args.near, args.far);
    let same = directions(&c.near)
        .iter()
        .zip(directions(&c.far))
        .all(|(a, b)| (*a - b).length() < 1e-12);
    let far_bits = |d: f64| if d > args.locality { "far" } else { "near" };
    outln!(
        "robot 0 sees {} robots in the same directions in both: {}",
        radians.len(),
        if same { "yes" } else { "no" }
    );
    outln!(
        "with Locality Detection (c = {}): every point is {} in the near configuration and {} in the far one",
        num(args.locality),
        far_bits(args.near),
        far_bits(args.far)
    );
    outln!("angle_deg,leaves_near_hull,leaves_far_hull");
    let mut every = true;
    for k in 0..args.moves {
        let angle = 360.0 * k as f64 / args.moves as f64;
        let u = DVec2::from_angle(angle.to_radians());
        let (n, f) = (
            leaves_hull(&c.near, args.step, u),
            leaves_hull(&c.far, args.step, u),
        );
        every &= n || f;
        outln!("{},{n},{f}", num(angle));
    }
    outln!(
        "every move of length {} leaves the hull of one of them: {}",
        num(args.step),
        if every { "yes" } else { "no" }
    );
    if let Some(out) = &args.out {
        let files = monoculus_plot::plot_impossibility(&c, args.step, out)
            .map_err(|e| Failure::Other(e.into()))?;
        for f in files {
            outln!("{}", f.display());
        }
    }
    Ok(())
}
