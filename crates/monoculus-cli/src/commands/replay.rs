use std::path::{Path, PathBuf};

use monoculus_experiments::Cell;
use monoculus_experiments::output::{Paths, unique_stems};
use monoculus_experiments::positions::{
    check_trace_matches, read_trace_positions, trace_of_positions,
};
use monoculus_experiments::replay::{Limits, Replay, from_trace, record, title};

use super::{Failure, check_paths, pick_cell, thread_pool};

#[derive(clap::Args, Debug)]
pub struct ReplayArgs {
    /// An experiment config (TOML), or a `monoculus trace --positions` file
    /// (`*.positions.csv`: columns round, robot, x, y[, z]).
    source: PathBuf,
    /// The seed (default: the config's first seed).
    #[arg(long)]
    seed: Option<u64>,
    /// Which cell of a sweep (default: the config must have one cell).
    #[arg(long)]
    cell: Option<usize>,
    /// Override a config key by its dotted path (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
    /// The HTML page to write.
    #[arg(long)]
    out: Option<PathBuf>,
    /// Also (or only) write the animation as a GIF.
    #[arg(long)]
    gif: Option<PathBuf>,
    /// GIF size in pixels, WIDTHxHEIGHT.
    #[arg(long, default_value = "480x480")]
    gif_size: String,
    /// Most robots drawn (above it, every k-th robot is drawn).
    #[arg(long, default_value_t = Limits::default().max_drawn)]
    max_drawn: usize,
    /// Most megabytes of frames and Looks in the page (frames are thinned beyond it).
    #[arg(long, default_value_t = Limits::default().max_bytes >> 20)]
    max_mb: usize,
    /// Worker threads (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
}

fn parse_size(s: &str) -> Result<(u32, u32), Failure> {
    let bad = || {
        Failure::Input(format!(
            "--gif-size `{s}`: expected WIDTHxHEIGHT, e.g. 480x480, each 64 to 4096"
        ))
    };
    let (w, h) = s.split_once('x').ok_or_else(bad)?;
    let (w, h): (u32, u32) = (w.parse().map_err(|_| bad())?, h.parse().map_err(|_| bad())?);
    if !(64..=4096).contains(&w) || !(64..=4096).contains(&h) {
        return Err(bad());
    }
    Ok((w, h))
}

fn is_trace(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("csv"))
}

/// Whether `path` names a folder: it ends with a separator or is one.
fn is_dir(path: &Path) -> bool {
    path.as_os_str()
        .to_string_lossy()
        .ends_with(std::path::MAIN_SEPARATOR)
        || path.is_dir()
}

pub fn replay(args: ReplayArgs, registry: &monoculus_experiments::Registry) -> Result<(), Failure> {
    if args.out.is_none() && args.gif.is_none() {
        return Err(Failure::Input(
            "replay: give --out FILE.html, --gif FILE.gif, or both".into(),
        ));
    }
    if args.max_drawn == 0 || args.max_mb == 0 {
        return Err(Failure::Input(
            "replay: --max-drawn and --max-mb must be at least 1".into(),
        ));
    }
    let gif_size = parse_size(&args.gif_size)?;
    let limits = Limits {
        max_drawn: args.max_drawn,
        max_bytes: args.max_mb << 20,
        ..Limits::default()
    };
    if is_trace(&args.source) {
        if args.seed.is_some() || args.cell.is_some() || !args.set.is_empty() {
            return Err(Failure::Input(format!(
                "{}: a trace is one run already: --seed, --cell and --set apply to configs",
                args.source.display()
            )));
        }
        let mut paths = Paths::default();
        paths.input("the trace", &args.source);
        add_outputs(&mut paths, &args.out, &args.gif);
        check_paths(&paths)?;
        let trace = read_trace_positions(&args.source)?;
        if let Some(csv) = trace_of_positions(&args.source).filter(|p| p.exists()) {
            check_trace_matches(
                &csv,
                &args.source,
                trace.rounds.len(),
                trace.rounds[0].len(),
            )?;
        }
        let replay = from_trace(&trace, args.source.display().to_string(), limits);
        return write(&replay, args.out.clone(), args.gif.clone(), gif_size);
    }
    let config = super::ConfigArgs {
        config: args.source.clone(),
        set: args.set.clone(),
    };
    let exp = config.load(registry)?;
    let seed = args.seed.unwrap_or(exp.seeds[0]);
    let folders = [&args.out, &args.gif]
        .into_iter()
        .flatten()
        .all(|p| is_dir(p));
    let cells: Vec<&Cell> = if args.cell.is_none() && exp.cells.len() > 1 && folders {
        exp.cells.iter().collect()
    } else {
        match pick_cell(&exp, args.cell, &args.source) {
            Ok(cell) => vec![cell],
            Err(Failure::Input(m)) if args.cell.is_none() => {
                return Err(Failure::Input(format!(
                    "{m}, or give folders (ending in /) to --out and --gif for a page per cell"
                )));
            }
            Err(e) => return Err(e),
        }
    };
    // A page per cell: names distinct whatever the cells' values (two cells whose values
    // differ only in characters a file name cannot hold fall back to the cell index).
    let labels: Vec<String> = cells.iter().map(|c| label(&exp.name, c)).collect();
    let stems = unique_stems(&labels, &format!("{}_cell", exp.name));
    let name = |dir: &PathBuf, k: usize, ext: &str| {
        if is_dir(dir) {
            dir.join(format!("{}.{ext}", stems[k]))
        } else {
            dir.clone()
        }
    };
    let mut paths = config.paths(&exp);
    for k in 0..cells.len() {
        add_outputs(
            &mut paths,
            &args.out.as_ref().map(|p| name(p, k, "html")),
            &args.gif.as_ref().map(|p| name(p, k, "gif")),
        );
    }
    check_paths(&paths)?;
    let pool = thread_pool(args.threads)?;
    for (k, cell) in cells.into_iter().enumerate() {
        let heading = title(&exp.name, cell, seed);
        let replay = pool
            .install(|| record(cell, seed, heading, limits))
            .map_err(|e| Failure::Input(format!("{}: {e}", args.source.display())))?;
        write(
            &replay,
            args.out.as_ref().map(|p| name(p, k, "html")),
            args.gif.as_ref().map(|p| name(p, k, "gif")),
            gif_size,
        )?;
    }
    Ok(())
}

/// `<experiment>` or `<experiment>_<values of the swept keys>`: what a cell's page is
/// named after (made safe and distinct by [`unique_stems`]).
fn label(name: &str, cell: &Cell) -> String {
    let mut stem = name.to_string();
    for (_, v) in &cell.values {
        stem.push('_');
        stem.push_str(v);
    }
    stem
}

fn add_outputs(paths: &mut Paths, out: &Option<PathBuf>, gif: &Option<PathBuf>) {
    if let Some(o) = out {
        paths.output("--out", o);
    }
    if let Some(g) = gif {
        paths.output("--gif", g);
    }
}

fn write(
    replay: &Replay,
    out: Option<PathBuf>,
    gif: Option<PathBuf>,
    gif_size: (u32, u32),
) -> Result<(), Failure> {
    if let Some(out) = &out {
        create_parent(out)?;
        monoculus_plot::write_replay_html(replay, out).map_err(|e| Failure::Other(e.into()))?;
    }
    if let Some(gif) = &gif {
        create_parent(gif)?;
        monoculus_plot::write_replay_gif(replay, gif, gif_size)
            .map_err(|e| Failure::Other(e.into()))?;
    }
    let shown: Vec<String> = [&out, &gif]
        .into_iter()
        .flatten()
        .map(|p| p.display().to_string())
        .collect();
    outln!(
        "{}: {}; {} frames of {} {}, {} Looks; wrote {}",
        replay.title,
        replay.outcome,
        replay.frames.len(),
        replay.metrics.time.len(),
        if replay.ticks { "ticks" } else { "rounds" },
        replay.looks.len(),
        shown.join(" and ")
    );
    Ok(())
}

fn create_parent(path: &Path) -> Result<(), Failure> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)
            .map_err(|e| Failure::Other(anyhow::anyhow!("{}: {e}", dir.display())))?;
    }
    Ok(())
}
