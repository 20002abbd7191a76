//! `cargo bench`: the hot paths, measured by criterion (kept out of `cargo test`).
//! One realization, the full Cayley space of the Jansen leg, one component
//! walk (exhaustive linking and the lazy walk), one trace; the full analysis
//! (recognition → components, no self-check) of the small scenes, and the
//! recognition and four-cycle test of a 5000-step chain; and issue 12's other
//! target rows: the exact Cayley space against the classic fixed-tolerance
//! baseline on every bench scene, the 1000-step chain's lazy walk, and
//! `report` on a 100-step chain as a whole process.

use std::hint::black_box;

use caymos::analysis::{Scope, analyse_with};
use caymos::cayley_space::{Method, cayley_space};
use caymos::lazy::{LazyOptions, component_through};
use caymos::motion::{Stepper, component_segments, components};
use caymos::real::Jet;
use criterion::{BatchSize, Criterion, criterion_group, criterion_main};

/// The binary's allocator (see Cargo.toml), so these figures are `caymos bench`'s.
#[global_allocator]
static ALLOCATOR: caymos::alloc::Allocator = caymos::alloc::Allocator;

fn small_scenes(c: &mut Criterion) {
    for name in ["fourbar-crank-rocker", "jansen", "limacon"] {
        let scene = caymos::bundled::load(name).expect("bundled");
        c.bench_function(&format!("{name} full analysis (no self-check)"), |b| {
            b.iter(|| caymos::bench::full_analysis(black_box(&scene), None))
        });
    }
    let chain = caymos::generate::chain(5000);
    let linkage = caymos::linkage::Linkage::from_scene(&chain);
    let base = chain.base.map(|b| b.0);
    c.bench_function("5000-step chain recognition + four-cycle test", |b| {
        b.iter(|| {
            let dec = caymos::decompose::decompose(black_box(&linkage), base).expect("in class").expect("valid base");
            caymos::complexity::four_cycle_test(&dec)
        })
    });
}

fn hot_paths(c: &mut Criterion) {
    let scene = caymos::bundled::load("jansen").expect("bundled");
    let a = analyse_with(scene, None, Scope::Full).expect("analyses");
    let s = a.outcome.clone().expect("in class");
    let con = &s.construction;
    let jet = con.convert::<Jet<f64>>();
    let k = s.drawn_component.expect("drawn component");

    c.bench_function("realize one Jansen realization", |b| {
        b.iter(|| con.realize(black_box(s.drawn.lambda), black_box(&s.drawn.ty)))
    });
    // Each run asks a fresh fork of the certifier (made untimed): its caches
    // start empty, as in one analysis.
    let fresh = || s.certifier.fork();
    c.bench_function("Jansen full Cayley space (exact)", |b| {
        b.iter_batched(
            fresh,
            |cert| cayley_space(con, &cert, &s.dec, &s.complexity, black_box(Method::Exact)),
            BatchSize::SmallInput,
        )
    });
    c.bench_function("Jansen components from the Cayley space", |b| b.iter(|| components(black_box(&s.space))));
    c.bench_function("Jansen lazy walk of the drawn component", |b| {
        b.iter_batched(
            fresh,
            |cert| component_through(con, &cert, &jet, &s.drawn.ty, black_box(s.drawn.lambda), LazyOptions::default()),
            BatchSize::SmallInput,
        )
    });
    let segments = component_segments(&s.space, &s.components.list[k]);
    let step = a.linkage.scale / 100.0;
    c.bench_function("Jansen trace of the drawn component (1% steps)", |b| {
        b.iter(|| Stepper::new(con, &a.linkage, segments.clone(), black_box(step)).count())
    });

    lazy_walk(c, 100);
}

/// The lazy walk of an n-step chain's drawn component.
fn lazy_walk(c: &mut Criterion, steps: usize) {
    let chain = caymos::generate::chain(steps);
    let ca = analyse_with(chain, None, Scope::Lazy).expect("analyses");
    let cs = ca.outcome.expect("in class");
    let cjet = cs.construction.convert::<Jet<f64>>();
    c.bench_function(&format!("{steps}-step chain lazy walk of the drawn component"), |b| {
        b.iter_batched(
            || cs.certifier.fork(),
            |cert| {
                component_through(
                    &cs.construction,
                    &cert,
                    &cjet,
                    &cs.drawn.ty,
                    black_box(cs.drawn.lambda),
                    LazyOptions::default(),
                )
            },
            BatchSize::SmallInput,
        )
    });
}

/// Exact (proven decisions) against classic (midpoints, 1e-4) on every scene `bench` times.
fn exact_vs_classic(c: &mut Criterion) {
    for b in caymos::bundled::BUNDLED {
        let Ok(a) = analyse_with(caymos::bundled::load(b.name).expect("bundled"), None, Scope::Full) else { continue };
        let Ok(s) = a.outcome else { continue };
        let con = &s.construction;
        c.bench_function(&format!("{} Cayley space exact", b.name), |bch| {
            bch.iter_batched(
                || s.certifier.fork(),
                |cert| cayley_space(con, &cert, &s.dec, &s.complexity, black_box(Method::Exact)),
                BatchSize::SmallInput,
            )
        });
        c.bench_function(&format!("{} Cayley space classic", b.name), |bch| {
            bch.iter(|| caymos::bench::classic_space(black_box(con), &s))
        });
    }
}

/// The 1000-step chain's drawn component by the lazy walk, and `report` on a
/// 100-step chain as the user runs it (a whole process: start, parse,
/// analysis, self-check, output).
fn large(c: &mut Criterion) {
    lazy_walk(c, 1000);
    let path = std::env::temp_dir().join(format!("caymos-bench-chain-100-{}.toml", std::process::id()));
    std::fs::write(&path, caymos::generate::to_toml(&caymos::generate::chain(100))).expect("temp file");
    c.bench_function("report on a 100-step chain, whole process", |b| {
        b.iter(|| {
            let out = std::process::Command::new(env!("CARGO_BIN_EXE_caymos"))
                .arg("report")
                .arg(&path)
                .output()
                .expect("the binary runs");
            assert!(out.status.success());
        })
    });
    let _ = std::fs::remove_file(&path);
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20);
    targets = small_scenes, hot_paths, exact_vs_classic
}
criterion_group! {
    name = slow;
    config = Criterion::default().sample_size(10);
    targets = large
}
criterion_main!(benches, slow);
