//! `monoculus plot`: figures from results folders and traces.

mod common;

use common::monoculus;

fn is_png(path: &std::path::Path) -> bool {
    std::fs::read(path).is_ok_and(|b| b.len() > 1000 && b.starts_with(b"\x89PNG"))
}

fn is_svg(path: &std::path::Path) -> bool {
    std::fs::read_to_string(path)
        .is_ok_and(|t| t.contains("<svg") && t.contains("</svg>") && t.len() > 1000)
}

#[test]
fn results_folders_give_box_plots_per_swept_key_and_algorithm() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = tmp.path().join("c.toml");
    std::fs::write(
        &cfg,
        "name = \"p\"\nseeds = 5\n[swarm]\nn = [8, 16]\ninit = \"square\"\nside = [6.0, 9.0]\n[algorithm]\nname = [\"converge_locality\", \"converge_quadrant\"]\n",
    )
    .unwrap();
    let out = tmp.path().join("out");
    assert!(
        monoculus(&["run", cfg.to_str().unwrap(), "--out", out.to_str().unwrap()])
            .status
            .success()
    );
    let o = monoculus(&["plot", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let fig = out.join("figures");
    for stem in [
        "rho_vs_n__side_6",
        "tau_vs_n__side_9",
        "rho_vs_side__n_16",
        "tau_vs_side__n_8",
        "rho_vs_n__side_6__converge_locality",
        "tau_vs_side__n_8__converge_quadrant",
    ] {
        assert!(
            is_png(&fig.join(format!("{stem}.png"))),
            "{stem}.png: {}",
            String::from_utf8_lossy(&o.stdout)
        );
        assert!(is_svg(&fig.join(format!("{stem}.svg"))), "{stem}.svg");
    }
    let svg = std::fs::read_to_string(fig.join("rho_vs_n__side_6.svg")).unwrap();
    assert!(
        svg.contains("converge_quadrant") && svg.contains("rho"),
        "legend and axis label are drawn"
    );
}

#[test]
fn a_single_cell_and_a_trace_plot_too() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = tmp.path().join("c.toml");
    std::fs::write(&cfg, "name = \"one\"\nseeds = 3\n[swarm]\nn = 12\ninit = \"square\"\nside = 8.0\n[algorithm]\nname = \"converge_locality\"\n").unwrap();
    let out = tmp.path().join("out");
    assert!(
        monoculus(&["run", cfg.to_str().unwrap(), "--out", out.to_str().unwrap()])
            .status
            .success()
    );
    assert!(
        monoculus(&[
            "plot",
            out.to_str().unwrap(),
            "--out",
            tmp.path().join("f").to_str().unwrap()
        ])
        .status
        .success()
    );
    assert!(is_png(&tmp.path().join("f/rho_vs_all_runs.png")));
    let trace = tmp.path().join("traces/t.csv");
    assert!(
        monoculus(&[
            "trace",
            cfg.to_str().unwrap(),
            "--seed",
            "2",
            "--out",
            trace.to_str().unwrap(),
            "--positions"
        ])
        .status
        .success()
    );
    assert!(
        monoculus(&["plot", trace.to_str().unwrap()])
            .status
            .success()
    );
    for f in ["t_series.png", "t_run.png"] {
        assert!(is_png(&tmp.path().join("traces").join(f)), "{f}");
    }
    assert!(is_svg(&tmp.path().join("traces/t_run.svg")));
}

#[test]
fn plotting_nothing_is_a_clear_error() {
    let tmp = tempfile::tempdir().unwrap();
    let o = monoculus(&["plot", tmp.path().to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("no runs.csv"));
    let o = monoculus(&["plot", tmp.path().join("missing.csv").to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    let bad = tmp.path().join("bad.csv");
    std::fs::write(&bad, "a,b\n1,2\n").unwrap();
    let o = monoculus(&["plot", bad.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        String::from_utf8_lossy(&o.stderr).contains("no column"),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
}
