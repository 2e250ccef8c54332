shapegen::generator! {
    struct G;
    start: A;
    node A {
        params {
            habit: int = uniform(0.5, 3.5),
            count: int = constant(2.0),
            level: int = constant(1.25),
        }
        |s| {}
    }
}
fn main() {}
