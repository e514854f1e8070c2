//! The programmable command language (doc/language.md, issue 54 items 1-3 and 6), through
//! the binary: expressions and their errors, queries of the scene against what PRint shows,
//! conditions, loops, procedures, INClude, `Cycle ... UNTIL`, `CALL ... EVery`, Ctrl-C in a
//! loop, the runaway loop, and SAve/RESTart in the middle of a procedure-driven run.

use std::path::PathBuf;
use std::process::Stdio;
use std::time::Duration;

use serde_json::Value;

/// A fresh directory holding `files`.
fn dir_with(tag: &str, files: &[(&str, &str)]) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("trubal-lang-{}-{tag}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    for (name, text) in files {
        std::fs::write(dir.join(name), text).unwrap();
    }
    dir
}

struct Out {
    code: Option<i32>,
    stdout: String,
    stderr: String,
}

/// `trubal --json ARGS main.tru` in `dir`.
fn run_in(dir: &PathBuf, args: &[&str]) -> Out {
    let o = crate::common::trubal()
        .current_dir(dir)
        .arg("--json")
        .args(args)
        .arg("main.tru")
        .output()
        .unwrap();
    Out {
        code: o.status.code(),
        stdout: String::from_utf8_lossy(&o.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&o.stderr).into_owned(),
    }
}

/// Runs `main` (and the other files) in a fresh directory.
fn run(tag: &str, main: &str, others: &[(&str, &str)]) -> Out {
    let mut files = vec![("main.tru", main)];
    files.extend_from_slice(others);
    let dir = dir_with(tag, &files);
    let out = run_in(&dir, &[]);
    let _ = std::fs::remove_dir_all(&dir);
    out
}

/// The values of every `SHow` line, in order.
fn shown(o: &Out) -> Vec<Vec<Value>> {
    o.stdout
        .lines()
        .filter_map(|l| serde_json::from_str::<Value>(l).ok())
        .filter_map(|v| v.get("show").and_then(|s| s.as_array().cloned()))
        .collect()
}

fn nums(o: &Out) -> Vec<Vec<f64>> {
    shown(o)
        .iter()
        .map(|row| row.iter().filter_map(|v| v.as_f64()).collect())
        .collect()
}

/// A scene of one sphere (R = 0.1 mm, glass-like) at (0.5, 0.5, 0.5) mm in a 1 mm box.
const ONE_BALL: &str = "start 1e-3 1e-3 1e-3 100 100 2
rad 1e-4 1
density 2650 1
ymd 70e9 1
pra 0.3 1
friction 0.3 1
create 5e-4 5e-4 5e-4 0 0 0 0 0 0 1 1
";

/// The same sphere at 1 m/s down.
const ONE_BALL_FALLING: &str = "start 1e-3 1e-3 1e-3 100 100 2
rad 1e-4 1
density 2650 1
ymd 70e9 1
pra 0.3 1
friction 0.3 1
create 5e-4 5e-4 5e-4 0 0 -1 0 0 0 1 1
";

#[test]
fn expressions_give_the_numbers_of_their_arithmetic() {
    let o = run(
        "expr",
        "let a = 3
let b = a^2 + 1          ; 10
let c = -2^2             ; -(2^2)
show a b c [(a + 1) * 2] [7 % 4] [sqrt(16) + abs(-1) + floor(2.5) + ceil(0.1) + round(2.5)]
show [max(1, 5, 3)] [min(2, -1)] [cos(pi)] [exp(0)] [log(1)] [log10(1000)] [atan2(1, 1)*4]
show [1 < 2 and not 2 < 1] [1 > 2 or 0] [a == 3] [a != 3] [1e-3*2] 1.d-3
",
        &[],
    );
    assert_eq!(o.code, Some(0), "{}", o.stderr);
    let v = nums(&o);
    assert_eq!(
        v[0],
        [3.0, 10.0, -4.0, 8.0, 3.0, 4.0 + 1.0 + 2.0 + 1.0 + 3.0]
    );
    assert_eq!(v[1], [5.0, -1.0, -1.0, 1.0, 0.0, 3.0, std::f64::consts::PI]);
    assert_eq!(v[2], [1.0, 0.0, 1.0, 0.0, 2e-3, 1e-3]);
}

#[test]
fn an_expression_stands_where_a_number_goes() {
    // `rad 1e-3*2 1` was refused before the language; the radius is the product.
    let o = run(
        "numbers",
        "let r0 = 1e-4
start 1e-3 1e-3 1e-3 100 100 2
rad 2*r0 1
rad [r0 / 2] 2
density 2650 1
ymd 70e9 1
pra 0.3 1
friction 0.3 1
create 5e-4 5e-4 [5e-4] 0 0 -r0 0 0 0 1 1
create [2.5e-4] 2.5e-4 2.5e-4 0 0 0 0 0 0 2 1
show [ball_r(1)] [ball_r(2)] [ball_vz(1)]
",
        &[],
    );
    assert_eq!(o.code, Some(0), "{}", o.stderr);
    assert_eq!(nums(&o)[0], [2e-4, 5e-5, -1e-4]);
}

#[test]
fn errors_name_the_file_line_and_column_and_change_nothing() {
    let o = run("err1", "let x = 5\nlet x = 1 + * 2\n", &[]);
    assert_eq!(o.code, Some(1));
    assert!(o.stderr.contains("main.tru:2:13: error"), "{}", o.stderr);
    // A failing LET leaves the variable as it was (keep going with --keep-going? no: a
    // terminal session would go on; the file stops, so show it from a second line set).
    let dir = dir_with(
        "err2",
        &[("main.tru", "let x = 5\nlet x = 1 / (x - 5)\nshow x\n")],
    );
    let o = run_in(&dir, &["--keep-going"]);
    let _ = std::fs::remove_dir_all(&dir);
    assert!(
        o.stderr.contains("main.tru:2:9: error: division by zero"),
        "{}",
        o.stderr
    );
    assert_eq!(nums(&o), [[5.0]]);
    // An unknown name is pointed at; a slash in a bare expression is refused with the
    // bracketed spelling (it would otherwise separate two numbers).
    let o = run("err3", "let r = 1\nshow [2 * rr]\n", &[]);
    assert!(
        o.stderr.contains("main.tru:2:11: error: unknown name `rr`"),
        "{}",
        o.stderr
    );
    let o = run("err4", "let r = 1\nshow r/2\n", &[]);
    assert!(
        o.stderr.contains("main.tru:2:6: error") && o.stderr.contains("`[r/2]`"),
        "{}",
        o.stderr
    );
    // The words of the old language keep their messages.
    let o = run("err5", "start 1 1 1 10 10 1\nrad abc 1\n", &[]);
    assert!(
        o.stderr
            .contains("main.tru:2:5: error: expected a number for `r`, found `abc`"),
        "{}",
        o.stderr
    );
}

#[test]
fn dollar_names_take_set_values_then_variables() {
    let dir = dir_with(
        "dollar",
        &[(
            "main.tru",
            "let n = 3\nlet m = 4\nshow $n $m\nsave \"a_$m.sav\"\n",
        )],
    );
    let o = run_in(&dir, &["--set", "n=7"]);
    assert_eq!(nums(&o), [[7.0, 4.0]], "{}", o.stderr);
    // SAve needs a scene: the name is substituted before that error is found.
    assert!(o.stderr.contains("no problem is defined"), "{}", o.stderr);
    let _ = std::fs::remove_dir_all(&dir);
}

/// Every number `PRint item` shows in JSON, read back by an expression `item.path`, is the
/// same bits.
#[test]
fn what_print_shows_an_expression_reads() {
    let mut script = String::from(ONE_BALL);
    script.push_str("create 5e-4 5e-4 2.5e-4 0 0 1 0 0 0 1 1\ndwall p 0 0 1 1e-4 m 1\ncycle 2000\nprint energy stress info walls chist clusters\n");
    let first = run("print1", &script, &[]);
    assert_eq!(first.code, Some(0), "{}", first.stderr);
    let mut paths = Vec::new();
    let mut want = Vec::new();
    fn leaves(v: &Value, path: String, out: &mut Vec<(String, f64)>) {
        match v {
            Value::Object(m) => {
                for (k, x) in m {
                    if k != "print" {
                        leaves(x, format!("{path}.{k}"), out);
                    }
                }
            }
            Value::Array(a) => {
                for (i, x) in a.iter().enumerate() {
                    leaves(x, format!("{path}.{}", i + 1), out);
                }
            }
            Value::Number(n) => out.push((path, n.as_f64().unwrap())),
            _ => {}
        }
    }
    for line in first.stdout.lines() {
        let Ok(v) = serde_json::from_str::<Value>(line) else {
            continue;
        };
        let Some(item) = v["print"].as_str() else {
            continue;
        };
        let mut out = Vec::new();
        leaves(&v, item.to_string(), &mut out);
        for (p, x) in out {
            paths.push(p);
            want.push(x);
        }
    }
    assert!(want.len() > 60, "{} numbers", want.len());
    for p in &paths {
        script.push_str(&format!("show [{p}]\n"));
    }
    script.push_str("show time cycle dt nball nwall [ball_z(2)] [ball_vz(2)] [ball_fz(2)] [wall_fz(1)] [wall_d(1)]\n");
    script.push_str("print balls walls\n");
    let o = run("print2", &script, &[]);
    assert_eq!(o.code, Some(0), "{}", o.stderr);
    let got = nums(&o);
    for (k, p) in paths.iter().enumerate() {
        assert_eq!(got[k], [want[k]], "{p}");
    }
    let q = got.last().unwrap();
    let info = crate::common::printed(
        &crate::common::Run {
            ok: true,
            code: o.code,
            stdout: o.stdout.clone(),
            stderr: String::new(),
        },
        "info",
    );
    assert_eq!(q[0], info[0]["time"].as_f64().unwrap());
    assert_eq!(q[1], 2000.0);
    assert_eq!(q[2], info[0]["dt"].as_f64().unwrap());
    assert_eq!(&q[3..5], [2.0, 1.0]);
    // The particle that hit the wall: its state as `PRint Balls` lists it.
    let printed_run = crate::common::Run {
        ok: true,
        code: o.code,
        stdout: o.stdout.clone(),
        stderr: String::new(),
    };
    let balls = &crate::common::printed(&printed_run, "balls")[0]["balls"];
    let b = balls
        .as_array()
        .unwrap()
        .iter()
        .find(|b| b["id"] == 2)
        .unwrap();
    assert_eq!(q[5], b["pos"][2].as_f64().unwrap(), "{b}");
    assert_eq!(q[6], b["vel"][2].as_f64().unwrap(), "{b}");
    let walls = &crate::common::printed(&printed_run, "walls")[0]["walls"][0];
    assert_eq!(q[8], walls["force"][2].as_f64().unwrap());
    assert_eq!(q[9], 1e-4);
    // Sums and averages over every particle: velocities given exactly.
    let o = run(
        "avg",
        &format!(
            "{ONE_BALL}create 2.5e-4 2.5e-4 2.5e-4 0 0 2 0 0 0 1 1\ncreate 7.5e-4 7.5e-4 7.5e-4 0 0 6 0 0 0 1 1\nshow [sum(vz)] [avg(vz)] [avg(x)] [sum(m)/nball]\n"
        ),
        &[],
    );
    let v = nums(&o);
    assert_eq!(v[0][0..2], [8.0, 8.0 / 3.0], "{}", o.stderr);
    assert_eq!(v[0][2], (5e-4 + 2.5e-4 + 7.5e-4) / 3.0);
    let m = 2650.0 * 4.0 / 3.0 * std::f64::consts::PI * 1e-12;
    assert!((v[0][3] / m - 1.0).abs() < 1e-12, "{} vs {m}", v[0][3]);
    let o = run("badpath", &format!("{ONE_BALL}show [energy.kinetc]\n"), &[]);
    assert!(
        o.stderr.contains("energy has no `kinetc`; it has")
            && o.stderr.contains("kinetic_translation"),
        "{}",
        o.stderr
    );
}

#[test]
fn conditions_loops_and_procedures() {
    let o = run(
        "flow",
        "let s = 0
loop i 1 10
  let s = s + i
end
show s i
loop k 10 1 -3
  show k
end
let n = 0
while 1
  let n = n + 1
  if n == 4
    break
  else
    if n > 4
      show \"never\"
    end
  end
end
show n
define fact m
  if m <= 1
    return 1
  end
  call fact [m - 1]
  return m * fact
end
let m = 99
call fact 10
show fact m
define twice x
  return 2 * x
  show \"never\"
end
call twice 21
show twice
",
        &[],
    );
    assert_eq!(o.code, Some(0), "{}", o.stderr);
    assert_eq!(
        nums(&o),
        [
            vec![55.0, 10.0],
            vec![10.0],
            vec![7.0],
            vec![4.0],
            vec![1.0],
            vec![4.0],
            vec![3628800.0, 99.0], // the parameter m is the call's own: the global is kept
            vec![42.0],
        ]
    );
    assert!(!o.stdout.contains("never"));
}

#[test]
fn block_errors_and_limits() {
    let cases: &[(&str, &str)] = &[
        ("end\n", "main.tru:1:1: error: ELSE and END close a block"),
        (
            "loop i 1 3\nshow i\n",
            "main.tru:1:1: error: this LOOP is not closed",
        ),
        (
            "while 1\nelse\nend\n",
            "main.tru:2:1: error: ELSE belongs to an IF",
        ),
        (
            "break\n",
            "main.tru:1:1: error: BREak outside a LOOP or WHILE",
        ),
        (
            "return\n",
            "main.tru:1:1: error: RETurn outside a procedure",
        ),
        ("call nope\n", "no procedure `nope`"),
        ("define f a\nend\ncall f\n", "f takes 1 argument (a), got 0"),
        (
            "loop i 1 1e7\nend\n",
            "main.tru:1:10: error: this LOOP would make 10000000 passes",
        ),
        (
            "define f\ncall f\nend\ncall f\n",
            "procedures nested more than 64 deep",
        ),
        ("let time = 1\n", "`time` is a query of the scene"),
        ("let sqrt = 1\n", "`sqrt` is a function or constant"),
        (
            "if 1 +\nend\n",
            "main.tru:1:7: error: the expression ends too soon",
        ),
    ];
    for (k, (script, want)) in cases.iter().enumerate() {
        let o = run(&format!("blk{k}"), script, &[]);
        assert_eq!(o.code, Some(1), "{script}");
        assert!(o.stderr.contains(want), "{script}: {}", o.stderr);
    }
    // A runaway loop is stopped after 10^6 passes, the state as after the last pass.
    let o = run(
        "runaway",
        "let k = 0\nwhile k >= 0\n  let k = k + 1\nend\n",
        &[],
    );
    assert!(
        o.stderr.contains(
            "main.tru:2:7: error: the condition is still true after 1000000 passes: a runaway loop"
        ),
        "{}",
        o.stderr
    );
}

#[test]
fn include_runs_another_file_and_names_its_lines() {
    let inc = "define bump by\n  let total = total + by\nend\n";
    let o = run(
        "inc",
        "let total = 0\ninclude inc.tru\ncall bump 2\ncall bump 3\nshow total\n",
        &[("inc.tru", inc)],
    );
    assert_eq!(o.code, Some(0), "{}", o.stderr);
    assert_eq!(nums(&o), [[5.0]]);
    // An error in a procedure defined in the included file names that file's line, and
    // the lines that led there.
    let o = run(
        "inc2",
        "include inc.tru\nloop i 1 2\n  call bump [i]\nend\n",
        &[("inc.tru", inc)],
    );
    assert!(
        o.stderr
            .contains("inc.tru:2:15: error: unknown name `total`"),
        "{}",
        o.stderr
    );
    assert!(o.stderr.contains("(from main.tru:3:"), "{}", o.stderr);
    let o = run("inc3", "include main.tru\n", &[]);
    assert!(
        o.stderr.contains("INClude nested more than 16 deep"),
        "{}",
        o.stderr
    );
}

#[test]
fn cycle_until_stops_after_the_first_step_at_which_it_holds() {
    // One sphere at 1 m/s in free flight: z falls by v dt a step. UNTIL stops at the first
    // cycle below 0.49 mm; a plain Cycle one shorter leaves it above.
    let o = run(
        "until",
        &format!(
            "{ONE_BALL_FALLING}cycle 100000 until ball_z(1) < 4.9e-4\nshow cycle [ball_z(1)] dt\n"
        ),
        &[],
    );
    assert_eq!(o.code, Some(0), "{}", o.stderr);
    let v = &nums(&o)[0];
    let (n, z, dt) = (v[0], v[1], v[2]);
    assert!(z < 4.9e-4);
    // The free flight's count: the first n with n v dt > 1e-5.
    assert_eq!(n, (1e-5 / dt).floor() + 1.0, "dt {dt}");
    let o = run(
        "until2",
        &format!(
            "{ONE_BALL_FALLING}cycle {}\nshow [ball_z(1)]\ncycle 10 until 0\nshow cycle\ncycle 10 until ball_z(1) < 1\n",
            n - 1.0
        ),
        &[],
    );
    let v = nums(&o);
    assert!(v[0][0] >= 4.9e-4, "{v:?}");
    assert_eq!(v[1][0], n - 1.0 + 10.0, "UNTIL never true: the maximum");
    assert!(o.stdout.contains("UNTIL already holds"), "{}", o.stdout);
}

/// A servo written in the language: a plane pushed down on a sphere until the wall's force
/// reaches a target, the speed set every 10 cycles.
const SERVO: &str = "start 1e-3 1e-3 1e-3 100 100 2
rad 1e-4 1
density 2650 1
ymd 70e9 1
pra 0.3 1
friction 0.3 1
fraction 0.2
create 5e-4 5e-4 1e-4 0 0 0 0 0 0 1 1
fix 1 1 1 1 1 1 1
dwall p 0 0 -1 -2.001e-4 m 1
let target = 1e-3
let calls = 0
define servo
  let calls = calls + 1
  let v = 2e-3 * (1 - abs(wall_fz(1)) / target)
  awall 1 v 0 0 -v
end
";

#[test]
fn a_procedure_every_k_cycles_is_a_servo() {
    let o = run(
        "servo",
        &format!(
            "{SERVO}cycle 20000 call servo every 10\nshow calls cycle [wall_fz(1)]\ncycle 5\ncycle 100 call servo every 10\nshow calls\n"
        ),
        &[],
    );
    assert_eq!(o.code, Some(0), "{}", o.stderr);
    let v = nums(&o);
    assert_eq!(v[0][..2], [2000.0, 20000.0]);
    // The servo holds the force at its target (the wall pushes down: fz of the wall > 0).
    assert!(
        (v[0][2].abs() / 1e-3 - 1.0).abs() < 0.01,
        "wall force {}",
        v[0][2]
    );
    // From cycle 20005, a call at 20010 ... 20100: ten.
    assert_eq!(v[1], [2010.0]);
    // Split in two Cycles, the same bits as one.
    let a = run(
        "servo_a",
        &format!("{SERVO}cycle 400 call servo every 10\nshow [wall_fz(1)] [wall_d(1)] calls\n"),
        &[],
    );
    let b = run(
        "servo_b",
        &format!(
            "{SERVO}cycle 130 call servo every 10\ncycle 270 call servo every 10\nshow [wall_fz(1)] [wall_d(1)] calls\n"
        ),
        &[],
    );
    assert_eq!(nums(&a), nums(&b));
    let o = run(
        "servo_c",
        &format!("{SERVO}define bad\n  cycle 1\nend\ncycle 20 call bad every 10\n"),
        &[],
    );
    assert!(o.stderr.contains("cannot cycle"), "{}", o.stderr);
}

/// SAve in the middle of a procedure-driven run (from inside the procedure the Cycle
/// calls), RESTart in a new process, the same commands after: the same bytes as the run
/// that went through.
#[test]
fn save_and_restart_in_a_procedure_driven_run_continue_bitwise() {
    let servo = SERVO.replace(
        "  awall 1 v 0 0 -v\n",
        "  awall 1 v 0 0 -v\n  if cycle == 300\n    save \"mid.sav\"\n  end\n",
    );
    let dir = dir_with(
        "ckpt",
        &[
            (
                "main.tru",
                &format!("{servo}cycle 600 call servo every 10\nsave \"a.sav\"\n"),
            ),
            (
                "b.tru",
                "restart \"mid.sav\"\ncycle 300 call servo every 10\nsave \"b.sav\"\nshow calls target\n",
            ),
        ],
    );
    let o = run_in(&dir, &[]);
    assert_eq!(o.code, Some(0), "{}", o.stderr);
    let o = crate::common::trubal()
        .current_dir(&dir)
        .args(["--json", "b.tru"])
        .output()
        .unwrap();
    let out = Out {
        code: o.status.code(),
        stdout: String::from_utf8_lossy(&o.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&o.stderr).into_owned(),
    };
    assert_eq!(out.code, Some(0), "{}", out.stderr);
    // The variables and the procedure came back with the state.
    assert_eq!(nums(&out), [[60.0, 1e-3]]);
    let a = std::fs::read(dir.join("a.sav")).unwrap();
    let b = std::fs::read(dir.join("b.sav")).unwrap();
    assert!(
        a == b,
        "the restarted run differs from the one that went through"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_loop_over_restarts_keeps_its_counter() {
    let dir = dir_with(
        "loopre",
        &[(
            "main.tru",
            &format!(
                "{ONE_BALL}let i = 99\nsave \"p.sav\"\nlet i = 0\nloop j 1 3\n  new\n  restart \"p.sav\"\n  create 2.5e-4 2.5e-4 2.5e-4 0 0 [-j] 0 0 0 1 1\n  cycle 10\n  show j i [ball_vz(2)]\nend\n"
            ),
        )],
    );
    let o = run_in(&dir, &[]);
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(o.code, Some(0), "{}", o.stderr);
    let v = nums(&o);
    assert_eq!(v, [[1.0, 99.0, -1.0], [2.0, 99.0, -2.0], [3.0, 99.0, -3.0]]);
}

/// Ctrl-C stops a loop that does not cycle, and a loop around a Cycle, and the file.
#[test]
fn ctrl_c_stops_any_loop() {
    for (tag, body) in [
        ("plain", "  let k = k + 1\n  show k\n"),
        ("cycling", "  let k = k + 1\n  cycle 20\n  show k\n"),
    ] {
        let dir = dir_with(
            &format!("int-{tag}"),
            &[(
                "main.tru",
                &format!("{ONE_BALL}let k = 0\nwhile k < 900000\n{body}end\nshow \"after\"\n"),
            )],
        );
        let mut child = crate::common::trubal()
            .current_dir(&dir)
            .arg("main.tru")
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let mut stdout = child.stdout.take().unwrap();
        // Wait for the loop's first line, then Ctrl-C.
        let mut first = [0u8; 2];
        std::io::Read::read_exact(&mut stdout, &mut first).unwrap();
        std::thread::sleep(Duration::from_millis(50));
        let st = std::process::Command::new("kill")
            .args(["-INT", &child.id().to_string()])
            .status()
            .unwrap();
        assert!(st.success());
        let mut rest = String::new();
        std::io::Read::read_to_string(&mut stdout, &mut rest).unwrap();
        let out = child.wait_with_output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        let _ = std::fs::remove_dir_all(&dir);
        assert_eq!(out.status.code(), Some(130), "{tag}: {err}");
        assert!(err.contains("interrupted"), "{tag}: {err}");
        assert!(!rest.contains("after"), "{tag}: the file stops");
        let shown = rest.lines().count();
        assert!(shown < 800000, "{tag}: {shown} passes after Ctrl-C");
    }
}

#[test]
fn help_knows_the_new_words() {
    let o = run("help", "help\nhelp let\nhelp loop\nhelp cycle until\n", &[]);
    for w in [
        "LET", "IF", "ELSE", "END", "LOOP", "WHILE", "DEFine", "CALL", "RETurn", "BREak",
        "INClude", "SHow",
    ] {
        assert!(
            o.stdout.contains(&format!("  {w} ")) || o.stdout.contains(&format!("  {w}\n")),
            "{w}: {}",
            o.stdout
        );
    }
    assert!(o.stdout.contains("ball_vz"), "{}", o.stdout);
    assert!(o.stdout.contains("Cycle UNTIL"), "{}", o.stdout);
}

/// `HIStory name EVery k expr`: recorded at the multiples of k across Cycles, the same bits
/// as the expression read after a plain Cycle to that cycle; printed, written to CSV,
/// charted, and carried through SAve/RESTart.
#[test]
fn histories_of_any_expression() {
    let dir = dir_with(
        "hist",
        &[
            (
                "main.tru",
                &format!(
                    "{ONE_BALL_FALLING}history zb every 7 ball_z(1) * 1e3\nhistory vz every 10 [ball_vz(1)]\ncycle 25\nsave \"h.sav\"\ncycle 5\nprint history\nhistory write \"h.csv\"\nplot history\n"
                ),
            ),
            ("b.tru", "restart \"h.sav\"\ncycle 5\nprint history\n"),
            (
                "c.tru",
                &format!("{ONE_BALL_FALLING}cycle 28\nshow [ball_z(1) * 1e3]\n"),
            ),
        ],
    );
    let o = run_in(&dir, &[]);
    assert_eq!(o.code, Some(0), "{}", o.stderr);
    let hist: Vec<Value> = o
        .stdout
        .lines()
        .filter_map(|l| serde_json::from_str::<Value>(l).ok())
        .filter(|v| v["print"] == "history" && v.get("name").is_some())
        .collect();
    assert_eq!(hist.len(), 2);
    let cycles = |h: &Value| -> Vec<u64> {
        h["rows"]
            .as_array()
            .unwrap()
            .iter()
            .map(|r| r[0].as_u64().unwrap())
            .collect()
    };
    assert_eq!(cycles(&hist[0]), [7, 14, 21, 28]);
    assert_eq!(cycles(&hist[1]), [10, 20, 30]);
    assert!(
        hist[1]["rows"]
            .as_array()
            .unwrap()
            .iter()
            .all(|r| r[2] == -1.0)
    );
    let c = crate::common::trubal()
        .current_dir(&dir)
        .args(["--json", "c.tru"])
        .output()
        .unwrap();
    let z28: Value = serde_json::from_slice(&c.stdout).unwrap();
    assert_eq!(
        hist[0]["rows"][3][2], z28["show"][0],
        "the record at cycle 28"
    );
    // The CSV file holds the same rows.
    let csv = std::fs::read_to_string(dir.join("h.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + 4 + 3, "{csv}");
    assert!(csv.starts_with("name,cycle,time,value\nzb,7,"), "{csv}");
    let png = std::fs::read(dir.join("plot_c00000030_histories.png")).unwrap();
    assert_eq!(&png[1..4], b"PNG");
    // Restarted at cycle 25, the history goes on with the same rows.
    let b = crate::common::trubal()
        .current_dir(&dir)
        .args(["--json", "b.tru"])
        .output()
        .unwrap();
    let hb: Vec<Value> = String::from_utf8_lossy(&b.stdout)
        .lines()
        .filter_map(|l| serde_json::from_str::<Value>(l).ok())
        .filter(|v| v["print"] == "history" && v.get("name").is_some())
        .collect();
    assert_eq!(hb, hist);
    let _ = std::fs::remove_dir_all(&dir);
    let o = run("hist_bad", "history h every 0 1\n", &[]);
    assert!(
        o.stderr
            .contains("main.tru:1:17: error: `k` must be at least 1"),
        "{}",
        o.stderr
    );
    let o = run("hist_bad2", "history h every 3 1 +\n", &[]);
    assert!(
        o.stderr
            .contains("main.tru:1:22: error: the expression ends too soon"),
        "{}",
        o.stderr
    );
}

/// An expression that runs to the end of the line may open with a bracket (the `(` that
/// separates TRUBAL's words is the expression's).
#[test]
fn an_expression_may_open_with_a_bracket() {
    let o = run(
        "paren",
        "let a = (1 + 2) / 3\nlet b = ((a + 1) * 2)\nif (b - 4) == 0\n  show a b\nend\n",
        &[],
    );
    assert_eq!(o.code, Some(0), "{}", o.stderr);
    assert_eq!(nums(&o), [[1.0, 4.0]]);
}

/// A number with a fraction keeps it wherever it ends the expression (the lexer once gave
/// `12.` for `12.75` at the end of the text).
#[test]
fn a_decimal_number_at_the_end_of_an_expression_keeps_its_fraction() {
    let o = run(
        "decimal",
        "let a = 12.75\nlet b = 0.5\nlet c = 1*2.75\nlet d = .5\nshow a b c d [0.5] [1.d-3] [2.5e1]\n",
        &[],
    );
    assert_eq!(o.code, Some(0), "{}", o.stderr);
    assert_eq!(nums(&o), [[12.75, 0.5, 2.75, 0.5, 0.5, 1e-3, 25.0]]);
}
