fn main() {
    let which = std::env::args().nth(1).unwrap();
    let res = verify::Resolution::Fast;
    let rows = match which.as_str() {
        "W1" => verify::w1::run(res), "W2" => verify::w2::run(res), "W3" => verify::w3::run(res),
        "W4" => verify::w4::run(res), "W5" => verify::w5::run(res), _ => verify::w6::run(res),
    };
    match rows { Ok(r) => for r in r { println!("{} {:<70} exp {:e} got {:e} tol {:e} {}", r.test, r.quantity, r.expected, r.measured, r.tolerance, r.pass) }, Err(e) => println!("ERR {e}") }
}
