// With a constant-expression length the compiler checks a constant index.
const PAIRS: usize = 2;

shapegen::generator! {
    struct G;
    start: A;
    node A {
        slots { pairs[PAIRS * 2]: A = 0.5 }
        |s| {
            child!(pairs[3], s);
            child!(pairs[4], s);
        }
    }
}
fn main() {}
