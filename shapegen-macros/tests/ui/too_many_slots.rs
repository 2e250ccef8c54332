const SIDE: usize = 20;

shapegen::generator! {
    struct G;
    start: A;
    node A {
        slots { lots[SIDE * SIDE]: A = 0.01 }
        |s| {}
    }
}
fn main() {}
