fn main() {
    println!("luxbake: not yet wired");
}
