//! `monoculus explore`: a live explorer in the browser. A local server (127.0.0.1 by
//! default, a random token in the address it prints) holds one [`session::Session`]
//! and serves one page that edits its start and settings, steps it, and shows what each
//! robot sees.

mod server;
mod session;

use std::path::PathBuf;

use monoculus_experiments::{Experiment, Registry};

use super::{Failure, pick_cell};

/// The settings of an explorer started without a config.
const DEFAULTS: &str = r#"name = "explore"
seeds = [0]

[swarm]
n = 12
init = "square"
side = 6.0

[algorithm]
name = "converge_locality"
step = 1.0
locality = 2.0

[scheduler]
kind = "fsync"

[stop]
max_rounds = 10000
"#;

#[derive(clap::Args, Debug)]
pub struct ExploreArgs {
    /// A config of one cell (or pick one with --cell), e.g. a hunt's reproduce.toml;
    /// without it, 12 robots of ConvergeLocality.
    config: Option<PathBuf>,
    /// The port (default: a free one).
    #[arg(long, default_value_t = 0)]
    port: u16,
    /// The address to listen on. Anything but a loopback address lets other machines
    /// reach the explorer (they still need its token).
    #[arg(long, default_value = "127.0.0.1")]
    host: String,
    /// The seed (default: the config's first seed).
    #[arg(long)]
    seed: Option<u64>,
    /// Which cell of a sweep (default: the config must have one cell).
    #[arg(long)]
    cell: Option<usize>,
    /// Override a config key by its dotted path (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
    /// Worker threads for the engine (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
}

pub fn explore(args: ExploreArgs, registry: &Registry) -> Result<(), Failure> {
    let mut set = args.set.clone();
    if let Some(seed) = args.seed {
        set.push(format!("seeds=[{seed}]"));
    }
    let (mut exp, label) = match &args.config {
        Some(path) => (
            Experiment::load(path, &set, registry)?,
            path.display().to_string(),
        ),
        None => {
            let mut defaults = DEFAULTS.to_string();
            if registry.get("converge_locality").is_none()
                && let Some(first) = registry.names().first()
            {
                defaults = defaults.replace("converge_locality", first);
            }
            let here = std::env::current_dir()?;
            (
                Experiment::parse(&defaults, "explore defaults", &here, &set, registry)?,
                "explore defaults".to_string(),
            )
        }
    };
    if args.cell.is_some() || exp.cells.len() == 1 {
        let cell = pick_cell(
            &exp,
            args.cell,
            args.config.as_deref().unwrap_or("explore".as_ref()),
        )?
        .clone();
        exp.cells = vec![cell];
    }
    let session = session::Session::new(exp, registry.clone())
        .map_err(|e| Failure::Input(format!("{label}: {}", e.0)))?;
    let pool = super::thread_pool(args.threads)?;
    server::serve(session, &args.host, args.port, pool)
}
