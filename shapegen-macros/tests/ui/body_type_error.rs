shapegen::generator! {
    struct G;
    shapes: [cube];
    start: A;
    node A emits {
        |s| {
            let n: u32 = "three";
            emit!(cube, s.instance());
        }
    }
}
fn main() {}
