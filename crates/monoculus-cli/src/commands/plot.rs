use std::path::PathBuf;

use monoculus_plot::{PlotError, plot_results, plot_trace};

use super::Failure;

#[derive(clap::Args, Debug)]
pub struct PlotArgs {
    /// A results folder (with runs.csv), or a trace CSV written by `monoculus trace`.
    path: PathBuf,
    /// Where to write the figures (default: DIR/figures for a results folder, the
    /// trace's folder for a trace).
    #[arg(long)]
    out: Option<PathBuf>,
}

impl From<PlotError> for Failure {
    fn from(e: PlotError) -> Self {
        match e {
            PlotError::Input { .. } => Failure::Input(e.to_string()),
            _ => Failure::Other(e.into()),
        }
    }
}

pub fn plot(args: PlotArgs) -> Result<(), Failure> {
    let p = &args.path;
    let written = if p.is_dir() {
        if !p.join("runs.csv").exists() {
            return Err(Failure::Input(format!(
                "{}: no runs.csv; run an experiment into it first",
                p.display()
            )));
        }
        plot_results(p, &args.out.clone().unwrap_or_else(|| p.join("figures")))?
    } else if p.is_file() {
        let dir = p.parent().map(PathBuf::from).unwrap_or_default();
        plot_trace(p, &args.out.clone().unwrap_or(dir))?
    } else {
        return Err(Failure::Input(format!(
            "{}: no such results folder or trace file",
            p.display()
        )));
    };
    for f in &written {
        outln!("{}", f.display());
    }
    Ok(())
}
