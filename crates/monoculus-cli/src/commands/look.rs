use std::path::PathBuf;

use monoculus_core::vision::{Sight, VisionParams};
use monoculus_engine::IndexedSight;
use monoculus_experiments::positions::read_positions;
use monoculus_experiments::results::num;

use super::Failure;

#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
enum Model {
    /// Locality Detection: direction and far bit.
    Ld,
    /// Orthogonal Line Agreement: direction and side of each agreed axis.
    Ola,
}

#[derive(clap::Args, Debug)]
pub struct LookArgs {
    /// Positions CSV (header x,y).
    positions: PathBuf,
    /// The observing robot: 0-based row of the CSV.
    #[arg(long)]
    robot: usize,
    /// Sensing model.
    #[arg(long, value_enum, default_value = "ld")]
    model: Model,
    /// Locality constant c (LD).
    #[arg(long, default_value_t = 2.0)]
    locality: f64,
}

/// Prints one row per visible point: `index` (lowest CSV row of co-located robots),
/// `far` (LD) or `side_x,side_y` (OLA: -1, 0 or 1 beyond the tolerance), and the unit
/// direction `dx,dy` in the global frame.
pub fn look(args: LookArgs) -> Result<(), Failure> {
    let pts = read_positions(&args.positions)?;
    if args.robot >= pts.len() {
        return Err(Failure::Input(format!(
            "--robot {}: {} has {} robots (rows 0..{})",
            args.robot,
            args.positions.display(),
            pts.len(),
            pts.len()
        )));
    }
    if !(args.locality > 0.0 && args.locality.is_finite()) {
        return Err(Failure::Input(format!(
            "--locality {}: must be positive",
            args.locality
        )));
    }
    let vision = VisionParams::default();
    let sight = IndexedSight::new(pts.clone(), vision);
    let p = pts[args.robot];
    match args.model {
        Model::Ld => println!("index,far,dx,dy"),
        Model::Ola => println!("index,side_x,side_y,dx,dy"),
    }
    for j in sight.visible_points(args.robot) {
        let d = pts[j] - p;
        let u = d.normalize();
        match args.model {
            Model::Ld => println!(
                "{j},{},{},{}",
                d.length() > args.locality,
                num(u.x),
                num(u.y)
            ),
            Model::Ola => {
                let side = |c: f64| {
                    if c > vision.eps_axis {
                        1
                    } else if c < -vision.eps_axis {
                        -1
                    } else {
                        0
                    }
                };
                println!("{j},{},{},{},{}", side(d.x), side(d.y), num(u.x), num(u.y));
            }
        }
    }
    Ok(())
}
