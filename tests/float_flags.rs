//! Every real-valued flag of `prism` and `interior`, given arbitrary f64
//! bit patterns (NaN, infinities, subnormals, huge and tiny values, and
//! random bits): the run ends in time with exit 0 and an image (the image
//! writers refuse NaN and infinity, so an image means finite pixels), or
//! with a clear error (one line, or clap's message and hint); never a
//! panic, a hang or a NaN.

use crate::common::*;
use proptest::prelude::*;
use refract::params::Kind;
use std::process::Stdio;
use std::time::{Duration, Instant};

/// The flags that take reals (one real, or one of three), by mode.
fn real_flags() -> Vec<(&'static str, String, bool)> {
    let mut v = Vec::new();
    for p in refract::params::prism::PARAMS {
        match p.kind {
            Kind::Real { .. } => v.push(("prism", p.key.replace('_', "-"), false)),
            Kind::Triple => v.push(("prism", p.key.replace('_', "-"), true)),
            _ => {}
        }
    }
    for p in refract::params::interior::PARAMS {
        match p.kind {
            Kind::Real { .. } => v.push(("interior", p.key.replace('_', "-"), false)),
            Kind::Triple => v.push(("interior", p.key.replace('_', "-"), true)),
            _ => {}
        }
    }
    v
}

fn check(mode: &str, flag: &str, triple: bool, x: f64) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o.png");
    let value = if triple { format!("0.1,{x:e},0.2") } else { format!("{x:e}") };
    let mut args: Vec<String> = vec![mode.into(), format!("--{flag}={value}"), "--size".into(), "24,16".into(), "--out".into(), out.display().to_string()];
    if mode == "prism" {
        args.extend(["--photons".into(), "2000".into(), "--spp".into(), "1".into()]);
    } else {
        args.extend(["--off".into(), repo("off/cube.off").display().to_string()]);
    }
    let mut child = bin().args(&args).current_dir(dir.path()).stdin(Stdio::null()).stdout(Stdio::null()).stderr(Stdio::piped()).spawn().unwrap();
    let start = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        if start.elapsed() > Duration::from_secs(60) {
            let _ = child.kill();
            panic!("{mode} --{flag}={value}: still running after 60 s");
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    let mut err = String::new();
    std::io::Read::read_to_string(child.stderr.as_mut().unwrap(), &mut err).unwrap();
    assert!(!err.contains("panicked"), "{mode} --{flag}={value}: {err}");
    match status.code() {
        Some(0) => assert!(out.is_file(), "{mode} --{flag}={value}: exit 0 and no image"),
        Some(1) => {
            assert_eq!(err.trim_end().lines().count(), 1, "{mode} --{flag}={value}: {err}");
            assert!(!out.exists());
        }
        c => panic!("{mode} --{flag}={value}: exit {c:?}: {err}"),
    }
}

fn interesting() -> impl Strategy<Value = f64> {
    prop_oneof![
        Just(f64::NAN),
        Just(f64::INFINITY),
        Just(f64::NEG_INFINITY),
        Just(0.0),
        Just(-0.0),
        Just(f64::MIN_POSITIVE),
        Just(5e-324),
        Just(1e-155),
        Just(1e300),
        Just(-1e300),
        Just(89.999999),
        Just(-90.0),
        any::<u64>().prop_map(f64::from_bits),
        (-1e3f64..1e3),
    ]
}

#[test]
fn every_special_value_on_every_real_flag() {
    let flags = real_flags();
    assert!(flags.len() >= 8, "{flags:?}");
    for (mode, flag, triple) in &flags {
        for x in [f64::NAN, f64::INFINITY, -1e300, 1e-300, 0.0] {
            check(mode, flag, *triple, x);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, failure_persistence: None, ..ProptestConfig::default() })]
    #[test]
    fn arbitrary_bits_on_any_real_flag(k in 0usize..64, x in interesting()) {
        let flags = real_flags();
        let (mode, flag, triple) = &flags[k % flags.len()];
        check(mode, flag, *triple, x);
    }
}
