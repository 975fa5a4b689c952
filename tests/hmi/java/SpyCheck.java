// lcm-spy's own window (lcm.spy.Spy, from Debian's lcm.jar) on an LCM url,
// with build/lib/softplc_hmi.jar on the class path, as build/bin/plc-lcm-spy
// runs it. Waits (300 tries, 100 ms apart) until Spy has received and
// decoded a message on each channel named, prints what Spy decoded:
//
//   channel NAME type CLASS received N
//   value INDEX TEXT            (the last softplc_hmi.values_t, field by field)
//   var PATH TYPE               (the last softplc_hmi.cell_description_t)
//
// opens Spy's viewer of the values channel as a double click does, and
// saves a screenshot when given a PNG path. Exit 0 when every channel was
// decoded, 1 otherwise. tests/hmi/test_hmi_lcm_spy.cpp runs it under Xvfb.
//
//   java -cp lcm.jar:jchart2d.jar:softplc_hmi.jar:DIR SpyCheck URL PNG|- CHANNEL...
import java.awt.Rectangle;
import java.awt.Robot;
import java.awt.Toolkit;
import java.io.File;
import java.lang.reflect.Field;
import java.lang.reflect.Method;
import java.util.ArrayList;
import java.util.HashMap;
import java.util.List;
import javax.imageio.ImageIO;
import javax.swing.SwingUtilities;
import lcm.spy.ChannelData;
import lcm.spy.Spy;

public class SpyCheck {
  public static void main(String[] args) throws Exception {
    if (args.length < 3) {
      System.err.println("usage: SpyCheck URL PNG|- CHANNEL...");
      System.exit(2);
    }
    final Spy spy = new Spy(args[0]);
    Field mapField = Spy.class.getDeclaredField("channelMap");
    mapField.setAccessible(true);
    @SuppressWarnings("unchecked")
    final HashMap<String, ChannelData> map = (HashMap<String, ChannelData>) mapField.get(spy);
    List<String> wanted = new ArrayList<>();
    for (int i = 2; i < args.length; ++i) wanted.add(args[i]);
    boolean all = false;
    for (int tries = 0; tries < 300 && !all; ++tries) {
      all = true;
      try {
        for (String ch : wanted) {
          ChannelData cd = map.get(ch);
          all &= cd != null && cd.cls != null && cd.last != null;
        }
      } catch (RuntimeException e) {  // the map changed under us: look again
        all = false;
      }
      if (!all) Thread.sleep(100);
    }
    for (String ch : wanted) {
      ChannelData cd = map.get(ch);
      System.out.println("channel " + ch + " type "
          + (cd == null || cd.cls == null ? "?" : cd.cls.getName()) + " received "
          + (cd == null ? 0 : cd.nreceived));
      if (cd == null || cd.last == null) continue;
      print(cd.last);
    }
    if (all && !args[1].equals("-")) {
      final ChannelData values = map.get(wanted.get(0));
      final Method create = Spy.class.getDeclaredMethod("createViewer", ChannelData.class);
      create.setAccessible(true);
      SwingUtilities.invokeAndWait(() -> {
        try {
          create.invoke(spy, values);
          values.viewer.setObject(values.last, values.last_utime);
          values.viewerFrame.setBounds(480, 0, 800, 700);
        } catch (Exception e) {
          throw new RuntimeException(e);
        }
      });
      Robot robot = new Robot();
      robot.waitForIdle();
      SwingUtilities.invokeAndWait(() -> values.viewerFrame.repaint());
      robot.waitForIdle();
      Rectangle screen = new Rectangle(Toolkit.getDefaultToolkit().getScreenSize());
      ImageIO.write(robot.createScreenCapture(screen), "png", new File(args[1]));
    }
    System.out.flush();
    System.exit(all ? 0 : 1);
  }

  // What Spy decoded, read back through the generated classes' fields.
  static void print(Object o) throws Exception {
    Class<?> c = o.getClass();
    if (c.getName().equals("softplc_hmi.values_t")) {
      for (Object v : (Object[]) c.getField("values").get(o)) {
        Class<?> vc = v.getClass();
        System.out.println("value " + vc.getField("index").get(v) + " " + vc.getField("text").get(v));
      }
    } else if (c.getName().equals("softplc_hmi.cell_description_t")) {
      for (Object v : (Object[]) c.getField("vars").get(o)) {
        Class<?> vc = v.getClass();
        System.out.println("var " + vc.getField("path").get(v) + " " + vc.getField("type").get(v));
      }
    }
  }
}
