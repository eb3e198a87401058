use std::path::PathBuf;

use glam::{DVec2, DVec3};
use monoculus_engine::IndexPoint;
use monoculus_experiments::positions::read_positions;

use super::Failure;

#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
enum Model {
    /// Locality Detection: direction and far bit.
    Ld,
    /// Orthogonal Line Agreement: direction and side of each agreed axis.
    Ola,
    /// Directions only.
    Directions,
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
    let model = match args.model {
        Model::Ld => monoculus_core::algorithms::Model::Ld,
        Model::Ola => monoculus_core::algorithms::Model::Ola,
        Model::Directions => monoculus_core::algorithms::Model::Directions,
    };
    monoculus_experiments::look::look_csv(pts, args.robot, model, args.locality)
}
