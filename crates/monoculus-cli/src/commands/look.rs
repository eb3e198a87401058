use std::path::PathBuf;

use glam::{DVec2, DVec3};
use monoculus_core::observe::inspect;
use monoculus_core::vision::VisionParams;
use monoculus_engine::{IndexPoint, IndexedSight};
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
/// `far` (LD) or `side_x,side_y[,side_z]` (OLA: -1, 0 or 1 beyond the tolerance), and
/// the unit direction `dx,dy[,dz]` in the global frame. A file with a `z` column is a
/// configuration in space.
pub fn look(args: LookArgs) -> Result<(), Failure> {
    let file = read_positions(&args.positions)?;
    if args.robot >= file.len() {
        return Err(Failure::Input(format!(
            "--robot {}: {} has {} robots (rows 0..{})",
            args.robot,
            args.positions.display(),
            file.len(),
            file.len()
        )));
    }
    if !(args.locality > 0.0 && args.locality.is_finite()) {
        return Err(Failure::Input(format!(
            "--locality {}: must be positive",
            args.locality
        )));
    }
    if file.has_z {
        out!("{}", look_in::<DVec3>(file.points(), &args));
    } else {
        out!("{}", look_in::<DVec2>(file.points(), &args));
    }
    Ok(())
}

fn look_in<P: IndexPoint>(pts: Vec<P>, args: &LookArgs) -> String {
    let axes = &["x", "y", "z"][..P::DIM];
    let sight = IndexedSight::new(pts, VisionParams::default());
    let mut out = String::new();
    let header: Vec<String> = match args.model {
        Model::Ld => ["index".to_string(), "far".to_string()]
            .into_iter()
            .chain(axes.iter().map(|a| format!("d{a}")))
            .collect(),
        Model::Ola => std::iter::once("index".to_string())
            .chain(axes.iter().map(|a| format!("side_{a}")))
            .chain(axes.iter().map(|a| format!("d{a}")))
            .collect(),
    };
    out.push_str(&header.join(","));
    out.push('\n');
    for seen in inspect(&sight, args.robot, args.locality) {
        let mut row = vec![seen.index.to_string()];
        match args.model {
            Model::Ld => row.push(seen.far.to_string()),
            Model::Ola => row.extend(seen.sides.iter().map(i8::to_string)),
        }
        row.extend((0..P::DIM).map(|k| num(seen.direction.axis(k))));
        out.push_str(&row.join(","));
        out.push('\n');
    }
    out
}
